#include "common/stripe/sensor_calibrator.h"

#include <numbers>

#include <gtest/gtest.h>

namespace ephor::stripe {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

double axis_angle_deg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)) / kDeg;
}

TEST(FindSpotTest, SubPixelCentroidOfTheDarkDisc) {
  const StripeScene table;
  StripeRendererOptions o;
  o.noise_sigma_grey = 0.0;
  o.spot_centre_mm = Eigen::Vector2d(3.3, -1.7);
  const SensorCalibration cage = SensorCalibration::drawing_cage();
  const StripeRenderer r(table, cage.camera, o);
  // Straight down from 300 mm over the origin: the spot's centre projects to
  // (cx, cy) + f (-x, y) / 300 (the camera's x axis is -x of the table).
  const Eigen::Isometry3d c = look_at({0, 0, 300}, {0, 0, 0}, Eigen::Vector3d::UnitY());
  const auto s = find_spot(r.render_ambient(c, 1));
  ASSERT_TRUE(s.has_value());
  const Eigen::Vector2d expected = cage.camera.project(c.inverse() * Eigen::Vector3d(3.3, -1.7, 0));
  EXPECT_LT((*s - expected).norm(), 0.05);
  EXPECT_FALSE(find_spot(cv::Mat(64, 64, CV_8UC1, cv::Scalar(170))).has_value());
}

// An ideal arm whose cage has the camera turned 1.5 deg (and the projector
// off by 2 mm and 1 deg): camera aim recovers the principal ray's direction,
// then the projector calibration the light plane.
TEST(SensorCalibratorTest, CameraAimThenProjectorPlaneRecoverTheTruth) {
  RobotTruth truth = RobotTruth::ideal();
  truth.cage.camera_in_flange.linear() =
      truth.cage.camera_in_flange.linear() *
      Eigen::AngleAxisd(1.5 * kDeg, Eigen::Vector3d(0.6, 0.8, 0.0)).toRotationMatrix();
  truth.cage.projector_in_flange.linear() =
      truth.cage.projector_in_flange.linear() *
      Eigen::AngleAxisd(1.0 * kDeg, Eigen::Vector3d(0.0, 0.6, 0.8)).toRotationMatrix();
  truth.cage.projector_in_flange.translation() += Eigen::Vector3d(2.0, -1.0, 0.5);
  const StripeScene table;
  const StripeWorld world(table, StripeWorkcell{}, truth);
  SimulatedRig rig(world, 5);
  const SensorCalibration drawing = SensorCalibration::drawing_cage();
  const TrueArm model = TrueArm::nominal();

  const Eigen::Vector3d true_axis = truth.cage.camera_in_flange.linear().col(2);
  EXPECT_NEAR(axis_angle_deg(drawing.camera_in_flange.linear().col(2), true_axis), 1.5, 0.01);
  const CameraAimResult aim =
      calibrate_camera_aim(rig, StripeWorkcell{}, model, drawing, Eigen::Vector2d(0, 0));
  EXPECT_NEAR(aim.correction_deg, 1.5, 0.1);
  EXPECT_LT(axis_angle_deg(aim.updated.camera_in_flange.linear().col(2), true_axis), 0.05);

  // With the true camera, the plane comes out exact up to extraction noise.
  SensorCalibration with_true_camera = drawing;
  with_true_camera.camera_in_flange = truth.cage.camera_in_flange;
  const ProjectorPlaneResult plane = calibrate_projector_plane(
      rig, StripeWorkcell{}, model, with_true_camera, Eigen::Vector2d(0, 0));
  const Eigen::Isometry3d& ts = truth.cage.projector_in_flange;
  const Eigen::Isometry3d& fs = plane.updated.projector_in_flange;
  EXPECT_NEAR(plane.normal_change_deg, axis_angle_deg(ts.linear().col(0), Eigen::Vector3d::UnitX()),
              0.02);
  EXPECT_LT(axis_angle_deg(fs.linear().col(0), ts.linear().col(0)), 0.02);
  EXPECT_LT(std::abs(ts.linear().col(0).dot(fs.translation() - ts.translation())), 0.05);
  EXPECT_LT(plane.rms_mm, 0.05);
  EXPECT_GT(plane.points, 2000u);
}

// An ideal arm whose camera is rolled 1.2 deg about its principal ray and
// magnifies 1 % more across and 0.5 % less down than the calibration file
// says: the scale-and-roll step finds all three.
TEST(SensorCalibratorTest, CameraScaleAndRollRecoverTheTruth) {
  RobotTruth truth = RobotTruth::ideal();
  truth.cage.camera_in_flange.linear() =
      truth.cage.camera_in_flange.linear() *
      Eigen::AngleAxisd(1.2 * kDeg, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  truth.cage.camera.fx_px *= 1.01;
  truth.cage.camera.fy_px *= 0.995;
  StripeRendererOptions o;
  o.noise_sigma_grey = 0.0;
  const StripeScene table;
  const StripeWorld world(table, StripeWorkcell{}, truth, o);
  SimulatedRig rig(world, 9);
  const SensorCalibration drawing = SensorCalibration::drawing_cage();
  const CameraScaleRollResult r = calibrate_camera_scale_and_roll(
      rig, StripeWorkcell{}, TrueArm::nominal(), drawing, Eigen::Vector2d(0, 0));
  EXPECT_NEAR(r.fx_ratio, 1.01, 0.001);
  EXPECT_NEAR(r.fy_ratio, 0.995, 0.001);
  EXPECT_NEAR(r.roll_correction_deg, 1.2, 0.02);
  EXPECT_NEAR(r.updated.camera.fx_px, truth.cage.camera.fx_px, 0.6);
  const Eigen::Matrix3d left =
      r.updated.camera_in_flange.linear().transpose() * truth.cage.camera_in_flange.linear();
  EXPECT_LT(Eigen::AngleAxisd(left).angle() / kDeg, 0.02);
}

}  // namespace
}  // namespace ephor::stripe
