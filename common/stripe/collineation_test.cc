#include "common/stripe/collineation.h"

#include <random>

#include <gtest/gtest.h>

namespace ephor::stripe {
namespace {

CameraIntrinsics test_camera() {
  CameraIntrinsics c;
  c.fx_px = c.fy_px = 500.0;
  c.cx_px = c.cy_px = 128.0;
  return c;
}

// Hand-checked: camera at the world origin looking along +z (C = I), f = 500
// px, principal point (128, 128); light plane x = 50 mm (S = translation
// (50, 0, 0)). Then R = P^-1 and the first row of Q = S^-1 R is
// [1/500, 0, -50, -0.256], so K = [[0.002, 0, -0.256], [0, 0.002, -0.256],
// [0, 0, 1], [0.00004, 0, -0.00512]] and the stripe point (228, 168) is the
// world point (0.2, 0.08, 1) / 0.004 = (50, 20, 250) mm.
TEST(CollineationTest, HandCheckedK) {
  Eigen::Isometry3d s = Eigen::Isometry3d::Identity();
  s.translation() = Eigen::Vector3d(50.0, 0.0, 0.0);
  const Collineation k(Eigen::Isometry3d::Identity(), s, test_camera());
  Collineation::Matrix43 expected;
  expected << 0.002, 0.0, -0.256,  //
      0.0, 0.002, -0.256,          //
      0.0, 0.0, 1.0,               //
      0.00004, 0.0, -0.00512;
  EXPECT_TRUE(k.K().isApprox(expected, 1e-12)) << k.K();
  const auto p = k.to_world(228.0, 168.0);
  ASSERT_TRUE(p.has_value());
  EXPECT_NEAR(p->x(), 50.0, 1e-9);
  EXPECT_NEAR(p->y(), 20.0, 1e-9);
  EXPECT_NEAR(p->z(), 250.0, 1e-9);
}

TEST(CollineationTest, PointBehindCameraIsRejected) {
  Eigen::Isometry3d s = Eigen::Isometry3d::Identity();
  s.translation() = Eigen::Vector3d(50.0, 0.0, 0.0);
  const Collineation k(Eigen::Isometry3d::Identity(), s, test_camera());
  // u < cx: the ray goes to negative x and meets x = 50 behind the camera.
  EXPECT_FALSE(k.to_world(28.0, 128.0).has_value());
  // u = cx: the ray is parallel to the plane.
  EXPECT_FALSE(k.to_world(128.0, 100.0).has_value());
}

TEST(CollineationTest, CameraInLightPlaneThrows) {
  EXPECT_THROW(
      Collineation(Eigen::Isometry3d::Identity(), Eigen::Isometry3d::Identity(), test_camera()),
      std::invalid_argument);
}

// The drawing cage on a flange at random poses: every stripe point maps to
// the intersection of its pixel's ray with the light plane, in the world.
TEST(CollineationTest, MatchesRayPlaneIntersectionOnTheCage) {
  const SensorCalibration cage = SensorCalibration::drawing_cage();
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> ang(-3.0, 3.0), pos(-500.0, 500.0), pix(0.0, 255.0);
  for (int trial = 0; trial < 20; ++trial) {
    Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
    t.linear() = (Eigen::AngleAxisd(ang(rng), Eigen::Vector3d::UnitZ()) *
                  Eigen::AngleAxisd(ang(rng), Eigen::Vector3d::UnitY()) *
                  Eigen::AngleAxisd(ang(rng), Eigen::Vector3d::UnitX()))
                     .toRotationMatrix();
    t.translation() = Eigen::Vector3d(pos(rng), pos(rng), pos(rng));
    const Collineation k = Collineation::from_flange(t, cage);
    const Eigen::Isometry3d c = t * cage.camera_in_flange, s = t * cage.projector_in_flange;
    const double u = pix(rng), v = pix(rng);
    const Eigen::Vector3d dir = c.linear() * cage.camera.ray(u, v);
    const Eigen::Vector3d n = s.linear().col(0);
    const double lambda = n.dot(s.translation() - c.translation()) / n.dot(dir);
    const auto p = k.to_world(u, v);
    ASSERT_EQ(p.has_value(), lambda > 0.0);
    if (p) {
      EXPECT_LT((*p - (c.translation() + lambda * dir)).norm(), 1e-6);
    }
  }
}

}  // namespace
}  // namespace ephor::stripe
