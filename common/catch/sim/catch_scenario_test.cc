#include "common/catch/sim/catch_scenario.h"

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

namespace ephor::catching {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

TEST(CatchScenarioTest, SameSeedSameScenario) {
  const CatchScenario a = CatchScenario::draw(7), b = CatchScenario::draw(7);
  EXPECT_EQ(a.placement.incline_rad, b.placement.incline_rad);
  ASSERT_EQ(a.pegs.size(), b.pegs.size());
  for (size_t i = 0; i < a.pegs.size(); ++i) {
    EXPECT_EQ(a.pegs[i].x_mm, b.pegs[i].x_mm);
    EXPECT_EQ(a.pegs[i].y_mm, b.pegs[i].y_mm);
  }
  EXPECT_TRUE(a.board_to_camera.matrix() == b.board_to_camera.matrix());
  EXPECT_EQ(a.release(3).x_mm, b.release(3).x_mm);
  const CatchScenario c = CatchScenario::draw(8);
  EXPECT_NE(a.placement.incline_rad, c.placement.incline_rad);
}

TEST(CatchScenarioTest, InclineLightingAndBallContrastWithinTheirRanges) {
  for (uint64_t seed = 1; seed <= 50; ++seed) {
    const CatchScenario s = CatchScenario::draw(seed);
    EXPECT_GE(s.placement.incline_rad, kInclineMinDeg * kDeg);
    EXPECT_LE(s.placement.incline_rad, kInclineMaxDeg * kDeg);
    EXPECT_GE(s.lighting.bands.size(), 2u);
    EXPECT_LE(s.lighting.bands.size(), 3u);
    EXPECT_GE(std::abs(s.appearance.ball_contrast), 4.0);
    EXPECT_LE(std::abs(s.appearance.ball_contrast), 8.0);
    EXPECT_NEAR(s.appearance.board_level, 120.0, 10.0);
  }
}

// The ball must never stick: every gap (peg-peg, peg-rail) is wider than the
// ball by 10 mm; pegs keep off the painted circles (the vision's landmarks),
// the release strip and the last 60 mm.
TEST(CatchScenarioTest, PegsKeepGapsAndNeverOverlapCircles) {
  for (uint64_t seed = 1; seed <= 50; ++seed) {
    const CatchScenario s = CatchScenario::draw(seed);
    const double rp = 0.5 * s.peg_diameter_mm;
    const double gap = s.board.ball_diameter_mm + 10.0;
    ASSERT_GE(static_cast<int>(s.pegs.size()), kPegsMin) << "seed " << seed;
    ASSERT_LE(static_cast<int>(s.pegs.size()), kPegsMax) << "seed " << seed;
    for (size_t i = 0; i < s.pegs.size(); ++i) {
      const Peg& p = s.pegs[i];
      EXPECT_GT(p.x_mm - rp, gap) << "seed " << seed << " peg " << i << " too near the left rail";
      EXPECT_GT(s.board.width_mm - p.x_mm - rp, gap) << "seed " << seed << " peg " << i;
      EXPECT_GE(p.y_mm - rp, kPegFreeTopMm) << "seed " << seed << " peg " << i;
      EXPECT_LE(p.y_mm + rp, s.board.height_mm - kPegFreeBottomMm) << "seed " << seed;
      for (size_t j = i + 1; j < s.pegs.size(); ++j) {
        const double centres = std::hypot(p.x_mm - s.pegs[j].x_mm, p.y_mm - s.pegs[j].y_mm);
        EXPECT_GT(centres - 2.0 * rp, gap) << "seed " << seed << " pegs " << i << ", " << j;
      }
      for (const BoardCircle& c : s.board.circles)
        EXPECT_GT(std::hypot(p.x_mm - c.x_mm, p.y_mm - c.y_mm), 0.5 * c.diameter_mm + rp + 10.0)
            << "seed " << seed << " peg " << i;
    }
  }
}

TEST(CatchScenarioTest, EverySeedSeesAllFourCornersFromAllowedPlace) {
  int draws = 0;
  for (uint64_t seed = 1; seed <= 50; ++seed) {
    const CatchScenario s = CatchScenario::draw(seed);
    draws += s.camera_draws;
    EXPECT_TRUE(s.corners_in_view(kCornerMarginPx)) << "seed " << seed;
    const Eigen::Vector3d cam_w = s.camera_position_w();
    EXPECT_GT(cam_w.z(), 300.0) << "seed " << seed;
    EXPECT_TRUE(cam_w.x() > 700.0 || cam_w.z() > 900.0) << "seed " << seed << " in the arm's space";
    const Eigen::Vector3d cam_b = s.board_to_camera.inverse().translation();
    EXPECT_GT(cam_b.z(), 0.0) << "seed " << seed << ": camera behind the board";
    const double d = (cam_b - Eigen::Vector3d(300.0, 450.0, 0.0)).norm();
    EXPECT_GE(d, 1200.0 - 1e-6);
    EXPECT_LE(d, 2000.0 + 1e-6);
    // The board centre is near the optical axis.
    const auto c = s.project(Eigen::Vector3d(300.0, 450.0, 0.0));
    ASSERT_TRUE(c.has_value());
    EXPECT_NEAR(c->x(), 319.5, 100.0);
    EXPECT_NEAR(c->y(), 239.5, 100.0);
  }
  std::cout << "camera poses drawn for seeds 1..50: " << draws << "\n";
}

TEST(CatchScenarioTest, ReleasesInTheStripWithTinyVelocity) {
  const CatchScenario s = CatchScenario::draw(11);
  const double r = s.board.ball_radius_mm();
  double min_x = 1e9, max_x = -1e9;
  for (int k = 0; k < 200; ++k) {
    const BallRelease b = s.release(k);
    EXPECT_GE(b.x_mm, r + 40.0);
    EXPECT_LE(b.x_mm, s.board.width_mm - r - 40.0);
    EXPECT_DOUBLE_EQ(b.y_mm, r + 10.0);
    EXPECT_LE(std::hypot(b.vx_mm_s, b.vy_mm_s), 5.0);
    EXPECT_GE(b.vy_mm_s, 0.0);
    min_x = std::min(min_x, b.x_mm), max_x = std::max(max_x, b.x_mm);
  }
  EXPECT_LT(min_x, 120.0);  // spread over the strip
  EXPECT_GT(max_x, 480.0);
  EXPECT_EQ(s.release(4).x_mm, s.release(4).x_mm);
  EXPECT_NE(s.release(4).x_mm, s.release(5).x_mm);
}

}  // namespace
}  // namespace ephor::catching
