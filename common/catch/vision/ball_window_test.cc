#include "common/catch/vision/ball_window.h"

#include <cmath>
#include <limits>
#include <stdexcept>

#include <gtest/gtest.h>

#include "common/catch/vision/test_scenes.h"

namespace ephor::catching {
namespace {

Eigen::Vector2d pixel(const SyntheticScene& s, const Eigen::Vector2d& xy) {
  return project_pinhole(s.camera, s.board_to_camera,
                         Eigen::Vector3d(xy.x(), xy.y(), s.board.ball_radius_mm()));
}

bool contains_with_margin(const cv::Rect& r, const Eigen::Vector2d& p, double margin) {
  return p.x() - margin >= r.x - 1 && p.x() + margin <= r.x + r.width + 1 &&
         p.y() - margin >= r.y - 1 && p.y() + margin <= r.y + r.height + 1;
}

TEST(BallWindowTest, CoversTheBallNowAndOneDifferenceGapAgo) {
  const SyntheticScene s = testing::board_scene(1500.0, 25.0);
  const BallWindow window(s.board, s.camera, s.board_to_camera);
  const Eigen::Vector2d p(300.0, 400.0), v(100.0, 1200.0);
  const auto w = window.around(p, v, 0.05);
  ASSERT_TRUE(w);
  const Eigen::Vector2d now = pixel(s, p + 0.05 * v),
                        before = pixel(s, p + (0.05 - 1.0 / 30.0) * v);
  EXPECT_TRUE(contains_with_margin(*w, now, 24.0));
  EXPECT_TRUE(contains_with_margin(*w, before, 24.0));
  // Not much larger than the two positions and the margins.
  EXPECT_LE(w->width, std::abs(now.x() - before.x()) + 2 * 24.0 + 3);
  EXPECT_LE(w->height, std::abs(now.y() - before.y()) + 2 * 24.0 + 3);
}

TEST(BallWindowTest, NoWindowForStaleOrBadEstimates) {
  const SyntheticScene s = testing::board_scene(1500.0, 25.0);
  const BallWindow window(s.board, s.camera, s.board_to_camera);
  const Eigen::Vector2d p(300.0, 400.0), v(0.0, 1000.0);
  EXPECT_FALSE(window.around(p, v, -0.001));  // estimate from the future
  EXPECT_FALSE(window.around(p, v, 0.2));     // too old to trust
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(window.around(Eigen::Vector2d(nan, 1.0), v, 0.01));
  EXPECT_FALSE(window.around(p, Eigen::Vector2d(0.0, nan), 0.01));
  // Far off the board and out of the image: nothing to look at.
  EXPECT_FALSE(window.around(Eigen::Vector2d(1e7, 1e7), Eigen::Vector2d::Zero(), 0.0));
}

TEST(BallWindowTest, ClippedToTheImage) {
  const SyntheticScene s = testing::board_scene(1500.0, 25.0);
  const BallWindow window(s.board, s.camera, s.board_to_camera, {60.0, 1.0 / 30.0, 0.1});
  const auto w = window.around(Eigen::Vector2d(0.0, 0.0), Eigen::Vector2d::Zero(), 0.0);
  ASSERT_TRUE(w);
  EXPECT_GE(w->x, 0);
  EXPECT_GE(w->y, 0);
  EXPECT_LE(w->x + w->width, s.camera.width);
  EXPECT_LE(w->y + w->height, s.camera.height);
}

TEST(BallWindowTest, BadOptionsAreRefused) {
  const SyntheticScene s = testing::board_scene(1500.0, 25.0);
  EXPECT_THROW(BallWindow(s.board, s.camera, s.board_to_camera, {0.0, 1.0 / 30.0, 0.1}),
               std::invalid_argument);
  EXPECT_THROW(BallWindow(s.board, s.camera, s.board_to_camera, {10.0, -1.0, 0.1}),
               std::invalid_argument);
}

}  // namespace
}  // namespace ephor::catching
