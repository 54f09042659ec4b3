#include "procs/catch/display/board_projector.h"

#include <gtest/gtest.h>

namespace ephor::catch_display {
namespace {

catching::CameraIntrinsics camera() {
  catching::CameraIntrinsics c;  // deploy/catch/camera.pbtxt
  c.width = 640;
  c.height = 480;
  c.fx = c.fy = 560.0;
  c.cx = 319.5;
  c.cy = 239.5;
  return c;
}

// The board face-on, 2 m in front of the camera, its centre on the optical axis.
catching::Pose face_on() {
  catching::Pose p = catching::Pose::Identity();
  p.translation() = Eigen::Vector3d(-300.0, -450.0, 2000.0);
  return p;
}

TEST(BoardProjectorTest, BoardCornersLandWhereThePinholePutsThem) {
  BoardProjector proj(camera());
  EXPECT_FALSE(proj.project_board({0, 0, 0}));  // no pose yet
  proj.set_board_to_camera(face_on());
  // u = 560 x / 2000 + 319.5, v = 560 y / 2000 + 239.5 with (x, y) = corner - (300, 450).
  const auto tl = proj.project_board({0, 0, 0});
  const auto br = proj.project_board({600, 900, 0});
  ASSERT_TRUE(tl && br);
  EXPECT_NEAR(tl->x(), 235.5, 1e-9);
  EXPECT_NEAR(tl->y(), 113.5, 1e-9);
  EXPECT_NEAR(br->x(), 403.5, 1e-9);
  EXPECT_NEAR(br->y(), 365.5, 1e-9);
  EXPECT_FALSE(proj.project_board({0, 0, -2500}));  // behind the camera
  EXPECT_FALSE(proj.project_board({std::nan(""), 0, 0}));
}

TEST(BoardProjectorTest, WorkCellPointsGoThroughTheBoard) {
  BoardProjector proj(camera());
  proj.set_board_to_camera(face_on());
  const catching::BoardSpec board;
  const catching::BoardPlacement placement;
  const auto b2w = catching::board_to_world(board, placement);
  EXPECT_FALSE(proj.project_world(b2w * Eigen::Vector3d(300, 450, 0)));  // not surveyed yet
  proj.set_board_to_world(b2w);
  EXPECT_TRUE(proj.knows_world());
  const Eigen::Vector3d p_b(123.0, 456.0, 20.0);
  const auto via_world = proj.project_world(b2w * p_b);
  const auto direct = proj.project_board(p_b);
  ASSERT_TRUE(via_world && direct);
  EXPECT_NEAR(via_world->x(), direct->x(), 1e-9);
  EXPECT_NEAR(via_world->y(), direct->y(), 1e-9);
}

TEST(BoardProjectorTest, DistortionMovesPointsOffTheAxis) {
  auto c = camera();
  c.distortion = {-0.2, 0.0, 0.0, 0.0};
  BoardProjector proj(c);
  proj.set_board_to_camera(face_on());
  const auto centre = proj.project_board({300, 450, 0});  // on the axis: not moved
  const auto corner = proj.project_board({0, 0, 0});
  ASSERT_TRUE(centre && corner);
  EXPECT_NEAR(centre->x(), 319.5, 1e-6);
  // Barrel distortion pulls the corner towards the centre: r^2 = 0.15^2 + 0.225^2.
  const double k = 1.0 - 0.2 * (0.15 * 0.15 + 0.225 * 0.225);
  EXPECT_NEAR(corner->x(), 319.5 - 560.0 * 0.15 * k, 1e-6);
  EXPECT_NEAR(corner->y(), 239.5 - 560.0 * 0.225 * k, 1e-6);
}

}  // namespace
}  // namespace ephor::catch_display
