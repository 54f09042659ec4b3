#include "common/catch/worldmodel/board_ray.h"

#include <gtest/gtest.h>

#include "common/catch/worldmodel/test_scene.h"

namespace ephor::catching {
namespace {

class BoardRayTest : public ::testing::Test {
 protected:
  BoardSpec board_;
  BoardPlacement placement_;
  CameraIntrinsics intrinsics_;
  Pose board_to_camera_ = testing::camera_looking_at_board(board_);
};

TEST_F(BoardRayTest, PixelOfBallCentreComesBackToTheCentre) {
  const BoardRay ray(board_, placement_, intrinsics_, board_to_camera_);
  const Pose b2w = board_to_world(board_, placement_);
  const double r = board_.ball_radius_mm();
  for (double x : {0.0, 150.0, 300.0, 600.0}) {
    for (double y : {0.0, 250.0, 450.0, 900.0}) {
      const Eigen::Vector3d centre(x, y, r);
      const auto px = ray.project(centre);
      ASSERT_TRUE(px.has_value());
      ASSERT_GT(px->x(), 0.0);  // the whole board is in the image
      ASSERT_LT(px->x(), intrinsics_.width - 1.0);
      ASSERT_GT(px->y(), 0.0);
      ASSERT_LT(px->y(), intrinsics_.height - 1.0);
      const BoardRayHit hit = ray.intersect(px->x(), px->y());
      ASSERT_TRUE(hit.ok());
      EXPECT_LT((hit.point_b_mm - centre).norm(), 1e-6) << x << ", " << y;
      EXPECT_LT((hit.point_w_mm - b2w * centre).norm(), 1e-6);
      EXPECT_NEAR(hit.range_mm, (board_to_camera_ * centre).norm(), 1e-6);
    }
  }
}

TEST_F(BoardRayTest, IgnoringTheRadiusMovesThePointAlongTheRay) {
  // Intersecting with the board face instead of z = +r puts the ball behind
  // its true position along the ray: offset_xy = -r (p - c)_xy / (p - c)_z
  // with c the camera centre in B.
  const BoardRay ray(board_, placement_, intrinsics_, board_to_camera_);
  const Eigen::Vector3d c = ray.camera_to_board().translation();
  const double r = board_.ball_radius_mm();
  for (const Eigen::Vector3d& centre :
       {Eigen::Vector3d(0.0, 0.0, r), Eigen::Vector3d(300.0, 450.0, r),
        Eigen::Vector3d(600.0, 900.0, r)}) {
    const auto px = ray.project(centre);
    ASSERT_TRUE(px.has_value());
    const BoardRayHit face = ray.intersect_at_height(px->x(), px->y(), 0.0);
    ASSERT_TRUE(face.ok());
    const Eigen::Vector3d d = centre - c;
    const Eigen::Vector2d expected = -r * d.head<2>() / d.z();
    const Eigen::Vector2d offset = (face.point_b_mm - centre).head<2>();
    EXPECT_LT((offset - expected).norm(), 1e-6);
    EXPECT_GT(offset.norm(), 2.0);  // mm: 2.4 to 12 mm here, against a 30 mm margin in the cup
  }
}

TEST_F(BoardRayTest, UndistortsWhenTheCameraHasDistortion) {
  intrinsics_.distortion = {-0.25, 0.08, 0.001, -0.0005, 0.0};
  const BoardRay ray(board_, placement_, intrinsics_, board_to_camera_);
  ASSERT_TRUE(ray.has_distortion());
  const BoardRay pinhole(board_, placement_, CameraIntrinsics{}, board_to_camera_);
  for (const Eigen::Vector3d& centre :
       {Eigen::Vector3d(20.0, 30.0, 20.0), Eigen::Vector3d(300.0, 450.0, 20.0),
        Eigen::Vector3d(580.0, 880.0, 20.0)}) {
    const auto px = ray.project(centre);
    ASSERT_TRUE(px.has_value());
    const BoardRayHit hit = ray.intersect(px->x(), px->y());
    ASSERT_TRUE(hit.ok());
    EXPECT_LT((hit.point_b_mm - centre).norm(), 1e-4);
    // Not undistorting would have been wrong by many mm at the corners.
    const BoardRayHit naive = pinhole.intersect(px->x(), px->y());
    if ((centre.head<2>() - Eigen::Vector2d(300.0, 450.0)).norm() > 100.0) {
      EXPECT_GT((naive.point_b_mm - centre).norm(), 5.0);
    }
  }
}

TEST_F(BoardRayTest, RayParallelToOrAwayFromThePlaneHasNoIntersection) {
  // A camera 500 mm above the board face looking along +y of B, image down
  // towards the board: the optical axis is parallel to the plane, rays above
  // it leave the board behind.
  Eigen::Matrix3d r_bc;
  r_bc.col(0) = Eigen::Vector3d(-1.0, 0.0, 0.0);  // x_C
  r_bc.col(1) = Eigen::Vector3d(0.0, 0.0, -1.0);  // y_C: towards the board
  r_bc.col(2) = Eigen::Vector3d(0.0, 1.0, 0.0);   // z_C: along +y of B
  const Eigen::Vector3d cam(300.0, -200.0, 500.0);
  Pose board_to_camera = Pose::Identity();
  board_to_camera.linear() = r_bc.transpose();
  board_to_camera.translation() = -r_bc.transpose() * cam;
  const BoardRay ray(board_, placement_, intrinsics_, board_to_camera);
  EXPECT_EQ(ray.intersect(intrinsics_.cx, intrinsics_.cy + 0.0).status, RayStatus::kParallel);
  EXPECT_EQ(ray.intersect(intrinsics_.cx, intrinsics_.cy - 50.0).status, RayStatus::kBehindCamera);
  EXPECT_TRUE(ray.intersect(intrinsics_.cx, intrinsics_.cy + 200.0).ok());
  EXPECT_EQ(ray.intersect(std::nan(""), 10.0).status, RayStatus::kNotFinite);
  EXPECT_FALSE(ray.project(Eigen::Vector3d(300.0, -500.0, 0.0)).has_value());  // behind it
}

TEST_F(BoardRayTest, RejectsBadIntrinsics) {
  intrinsics_.distortion = {0.1, 0.2, 0.3};
  EXPECT_THROW(BoardRay(board_, placement_, intrinsics_, board_to_camera_), std::invalid_argument);
  intrinsics_.distortion.clear();
  intrinsics_.fx = 0.0;
  EXPECT_THROW(BoardRay(board_, placement_, intrinsics_, board_to_camera_), std::invalid_argument);
}

}  // namespace
}  // namespace ephor::catching
