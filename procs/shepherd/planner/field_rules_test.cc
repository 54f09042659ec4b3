#include "procs/shepherd/planner/field_rules.h"

#include "common/arm/arm_workcell.h"

#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

namespace ephor::planner {
namespace {

Sheep sheep(int id, double x, double y, double vx, double vy) {
  return Sheep{id, x, y, vx, vy, SheepState::kVisible};
}

TEST(FieldRulesTest, TimeToBoundaryFromPositionAndVelocity) {
  const FieldRules rules{PlannerConfig{}};
  EXPECT_NEAR(rules.time_to_boundary(sheep(1, 100, 457, -20, 0)), 5.0, 1e-12);
  EXPECT_NEAR(rules.time_to_boundary(sheep(1, 1119, 457, 20, 0)), 5.0, 1e-12);
  // Diagonal: y reaches 914 in (914 - 814) / 10 = 10 s before x reaches 1219.
  EXPECT_NEAR(rules.time_to_boundary(sheep(1, 600, 814, 10, 10)), 10.0, 1e-12);
  EXPECT_TRUE(std::isinf(rules.time_to_boundary(sheep(1, 600, 400, 0, 0))));
  EXPECT_EQ(rules.time_to_boundary(sheep(1, -5, 400, 10, 0)), 0.0);
}

// predict_bounces: sheep 1 walks down to the bottom edge (30 s on its
// straight line) and sheep 2 comes up at it head-on from just above that edge
// (89 s to the top edge). They meet nose to nose within 3 s: sheep 2 is sent
// back down and leaves first, sheep 1 goes up and leaves last.
TEST(FieldRulesTest, WithPredictedBouncesTheOrderFollowsTheBouncedExits) {
  const std::vector<Sheep> herd{sheep(1, 300, 300, 0, -10), sheep(2, 300, 25, 0, 10)};
  PlannerConfig config;
  EXPECT_EQ(FieldRules{config}.candidates_by_urgency(herd), (std::vector<int>{0, 1}));
  config.predict_bounces = true;
  EXPECT_EQ(FieldRules{config}.candidates_by_urgency(herd), (std::vector<int>{1, 0}));
}

TEST(FieldRulesTest, HeadingToCentreWithinTheConfiguredAngle) {
  const FieldRules rules{PlannerConfig{}};  // 0.5 rad
  EXPECT_TRUE(rules.heading_to_centre(sheep(1, 100, 457, 30, 0)));
  EXPECT_TRUE(rules.heading_to_centre(sheep(1, 100, 457, 30 * std::cos(0.4), 30 * std::sin(0.4))));
  EXPECT_FALSE(rules.heading_to_centre(sheep(1, 100, 457, 30 * std::cos(0.6), 30 * std::sin(0.6))));
  EXPECT_FALSE(rules.heading_to_centre(sheep(1, 100, 457, -30, 0)));
  EXPECT_FALSE(rules.needs_saving(sheep(1, 100, 457, 30, 0)));
  EXPECT_TRUE(rules.needs_saving(sheep(1, 100, 457, -30, 0)));
  Sheep dead = sheep(1, 100, 457, -30, 0);
  dead.state = SheepState::kDead;
  EXPECT_FALSE(rules.needs_saving(dead));
  EXPECT_FALSE(rules.needs_saving(sheep(1, 100, 457, std::numeric_limits<double>::quiet_NaN(), 0)));
}

// The tool faces where the touched sheep will go. Alone on the field: past
// the pedestal (its centre line at least redirect_clearance_mm from the
// column's axis), within redirect_max_rad of the centre, so it still counts
// as headed toward the centre.
TEST(FieldRulesTest, RedirectHeadingPassesThePedestal) {
  PlannerConfig config;
  const FieldRules rules{config};
  const double bx = config.workcell.base_x_mm, by = config.workcell.base_y_mm;
  for (const auto& [x, y] : std::vector<std::pair<double, double>>{
           {100, 457}, {1119, 457}, {609.5, 40}, {200, 100}, {1000, 850}, {609.5 - 380, 457}}) {
    const Sheep target = sheep(1, x, y, -8, 0);
    const double h = rules.redirect_heading(x, y, {target}, 1);
    const double miss = std::abs(std::cos(h) * (by - y) - std::sin(h) * (bx - x));
    EXPECT_GE(miss, config.redirect_clearance_mm) << x << ", " << y;
    const double to_centre = std::atan2(rules.centre_y_mm() - y, rules.centre_x_mm() - x);
    EXPECT_LE(std::abs(std::remainder(h - to_centre, 2 * std::numbers::pi)),
              config.redirect_max_rad + 1e-9);
    EXPECT_TRUE(rules.heading_to_centre(sheep(1, x, y, 8 * std::cos(h), 8 * std::sin(h))));
  }
  // Clearance 0: straight at the centre, the paper's rule.
  config.redirect_clearance_mm = 0.0;
  EXPECT_NEAR(FieldRules{config}.redirect_heading(100, 457, {}, 1), 0.0, 1e-12);
}

// From the middle of the left edge the two ways past the pedestal are
// alike (the one above first); a sheep standing on the upper one makes the
// tool send it by the lower one.
TEST(FieldRulesTest, RedirectHeadingAvoidsAnotherSheepsPath) {
  const FieldRules rules{PlannerConfig{}};
  const Sheep target = sheep(1, 100, 457, -8, 0);
  const Sheep crossing = sheep(2, 400, 560, 0, 0);
  const double alone = rules.redirect_heading(100, 457, {target}, 1);
  const double with_other = rules.redirect_heading(100, 457, {target, crossing}, 1);
  EXPECT_GT(alone, 0.0);
  EXPECT_LT(with_other, 0.0) << "below the column";
  EXPECT_GT(rules.walk_free_s(100, 457, with_other, 8, {target, crossing}, 1),
            rules.walk_free_s(100, 457, std::abs(with_other), 8, {target, crossing}, 1));
  EXPECT_LT(rules.walk_free_s(100, 457, 0.0, 8, {target}, 1), 60.0) << "at the pedestal";
  EXPECT_GT(rules.walk_free_s(100, 457, alone, 8, {target}, 1), 100.0) << "past it, to the edge";
}

TEST(FieldRulesTest, UsablePointsAvoidTheEdgeAndThePedestal) {
  const FieldRules rules{PlannerConfig{}};
  EXPECT_TRUE(rules.usable_point(100, 100));
  EXPECT_FALSE(rules.usable_point(5, 100));  // field margin 10 mm
  EXPECT_FALSE(rules.usable_point(1215, 100));
  EXPECT_FALSE(rules.usable_point(609.5 + 300, 457));  // within 360 mm of the column
  EXPECT_TRUE(rules.usable_point(609.5 + 370, 457));
}

// The keep-out radius matches what the PUMA can reach with the tool down
// (common/arm): every usable point of the field on a 20 mm grid is reachable
// in both planes, and a smaller radius would not do.
TEST(FieldRulesTest, ToolKeepoutMatchesThePumasReach) {
  const PlannerConfig config;
  const FieldRules rules{config};
  const auto& w = config.workcell;
  int checked = 0;
  for (double y = 10; y <= w.field_width_mm - 10; y += 20) {
    for (double x = 10; x <= w.field_length_mm - 10; x += 20) {
      if (!rules.usable_point(x, y)) continue;
      const double theta = std::atan2(w.centre_y_mm() - y, w.centre_x_mm() - x);
      ASSERT_TRUE(arm::reachable_tool_down(w, x, y, w.elevation_plane_z_mm, theta))
          << "(" << x << ", " << y << ") elevation plane";
      ASSERT_TRUE(arm::reachable_tool_down(w, x, y, w.object_plane_z_mm, theta))
          << "(" << x << ", " << y << ") object plane";
      ++checked;
    }
  }
  EXPECT_GT(checked, 1500);
  // 320 mm from the column is out of reach in the elevation plane somewhere.
  bool some_unreachable = false;
  for (int k = 0; k < 36; ++k) {
    const double a = k * 2.0 * std::numbers::pi / 36.0;
    const double x = w.base_x_mm + 320.0 * std::cos(a);
    const double y = w.base_y_mm + 320.0 * std::sin(a);
    some_unreachable |= !arm::reachable_tool_down(
        w, x, y, w.elevation_plane_z_mm, std::atan2(w.centre_y_mm() - y, w.centre_x_mm() - x));
  }
  EXPECT_TRUE(some_unreachable);
}

TEST(FieldRulesTest, OtherSheepNearUsesPredictedPositions) {
  const FieldRules rules{PlannerConfig{}};  // clearance 120 mm
  // Sheep 2 starts 600 mm left of (700, 200) and moves right at 30 mm/s:
  // within 120 mm from t = 16 s to t = 24 s.
  const std::vector<Sheep> all{sheep(1, 500, 500, 0, 0), sheep(2, 100, 200, 30, 0)};
  EXPECT_EQ(rules.other_sheep_near(all, 1, 700, 200, 0.0, 5.0), -1);
  EXPECT_EQ(rules.other_sheep_near(all, 1, 700, 200, 10.0, 15.9), -1);
  EXPECT_EQ(rules.other_sheep_near(all, 1, 700, 200, 10.0, 16.1), 2);
  EXPECT_EQ(rules.other_sheep_near(all, 1, 700, 200, 23.9, 30.0), 2);
  EXPECT_EQ(rules.other_sheep_near(all, 1, 700, 200, 24.1, 30.0), -1);
  // The target itself never blocks.
  EXPECT_EQ(rules.other_sheep_near(all, 2, 700, 200, 10.0, 20.0), -1);
}

}  // namespace
}  // namespace ephor::planner
