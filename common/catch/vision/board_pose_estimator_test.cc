#include "common/catch/vision/board_pose_estimator.h"

#include <cmath>
#include <iostream>
#include <random>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "common/catch/vision/circle_finder.h"
#include "common/catch/vision/test_scenes.h"

namespace ephor::catching {
namespace {

constexpr double kPi = 3.14159265358979323846;

double angle_deg(const Pose& a, const Pose& b) {
  return Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle() * 180.0 / kPi;
}
double distance_mm(const Pose& a, const Pose& b) {
  return (a.translation() - b.translation()).norm();
}

std::array<Eigen::Vector2d, 4> projected_centres(const BoardPoseEstimator& est, const Pose& pose) {
  std::array<Eigen::Vector2d, 4> c;
  for (int i = 0; i < 4; ++i) c[static_cast<size_t>(i)] = est.project_circle(pose, i).centre_px;
  return c;
}

TEST(BoardPoseEstimatorTest, IppeRoundTripRecoversAKnownPose) {
  const SyntheticScene s = testing::board_scene(1500.0, 35.0, 20.0, 10.0);
  const BoardPoseEstimator est(s.board, s.camera);
  for (PnpMethod method : {PnpMethod::kIppe, PnpMethod::kIterative}) {
    const BoardPoseResult r = est.estimate(projected_centres(est, s.board_to_camera), {method, 0});
    ASSERT_TRUE(r.ok) << r.problem;
    EXPECT_LT(distance_mm(r.board_to_camera, s.board_to_camera), 1e-6);
    EXPECT_LT(angle_deg(r.board_to_camera, s.board_to_camera) * kPi / 180.0, 1e-6);
    EXPECT_LT(r.reprojection_rms_px, 1e-6);
  }
}

TEST(BoardPoseEstimatorTest, ProjectionWithDistortionRoundTrips) {
  SyntheticScene s = testing::board_scene(1500.0, 30.0);
  s.camera.distortion = {-0.12, 0.03, 0.0005, -0.0002, 0.0};
  const BoardPoseEstimator est(s.board, s.camera);
  std::array<Eigen::Vector2d, 4> c;
  for (size_t i = 0; i < 4; ++i)
    c[i] = est.project(s.board_to_camera,
                       Eigen::Vector3d(s.board.circles[i].x_mm, s.board.circles[i].y_mm, 0.0));
  const BoardPoseResult r = est.estimate(c, {PnpMethod::kIppe, 0});
  ASSERT_TRUE(r.ok);
  EXPECT_LT(distance_mm(r.board_to_camera, s.board_to_camera), 1e-3);
}

TEST(BoardPoseEstimatorTest, BothIppeSolutionsAreExaminedNearFrontoParallel) {
  // Near fronto-parallel the planar ambiguity is strongest: IPPE's second
  // solution is a plausible pose too.
  const SyntheticScene s = testing::board_scene(1500.0, 3.0, 40.0);
  const BoardPoseEstimator est(s.board, s.camera);
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 0.05);
  auto c = projected_centres(est, s.board_to_camera);
  for (auto& p : c) p += Eigen::Vector2d(noise(rng), noise(rng));
  const BoardPoseResult r = est.estimate(c, {PnpMethod::kIppe, 0});
  ASSERT_TRUE(r.ok);
  EXPECT_TRUE(std::isfinite(r.ippe_rms_px[0]));
  EXPECT_TRUE(std::isfinite(r.ippe_rms_px[1])) << "the second solution was not examined";
  EXPECT_GE(r.ippe_error_ratio, 1.0);
  EXPECT_LT(angle_deg(r.board_to_camera, s.board_to_camera), 0.5);
  EXPECT_LT(distance_mm(r.board_to_camera, s.board_to_camera), 5.0);
  std::cout << "near fronto-parallel: IPPE RMS " << r.ippe_rms_px[0] << " / " << r.ippe_rms_px[1]
            << " px, kept solution " << r.ippe_solution << ", ratio " << r.ippe_error_ratio << "\n";
}

TEST(BoardPoseEstimatorTest, PerspectiveBiasIsMeasurableAndRemoved) {
  // 60 degrees oblique at 1.2 m: the circles' image centroids (ellipse
  // centres) are not the images of their centres.
  const SyntheticScene s = testing::board_scene(1200.0, 60.0);
  const BoardPoseEstimator est(s.board, s.camera);
  std::array<Eigen::Vector2d, 4> centroids;
  double worst_bias = 0.0;
  for (int i = 0; i < 4; ++i) {
    const ProjectedCircle pc = est.project_circle(s.board_to_camera, i);
    centroids[static_cast<size_t>(i)] = pc.centroid_px;
    worst_bias = std::max(worst_bias, (pc.centroid_px - pc.centre_px).norm());
  }
  std::cout << "60 deg oblique, 1.2 m: largest perspective bias " << worst_bias << " px\n";
  EXPECT_GT(worst_bias, 0.2);
  for (PnpMethod method : {PnpMethod::kIppe, PnpMethod::kIterative}) {
    const BoardPoseResult raw = est.estimate(centroids, {method, 0});
    const BoardPoseResult fixed = est.estimate(centroids, {method, 3});
    ASSERT_TRUE(raw.ok && fixed.ok);
    const double raw_mm = distance_mm(raw.board_to_camera, s.board_to_camera);
    const double fixed_mm = distance_mm(fixed.board_to_camera, s.board_to_camera);
    std::cout << (method == PnpMethod::kIppe ? "IPPE" : "iterative") << ": pose error " << raw_mm
              << " mm " << angle_deg(raw.board_to_camera, s.board_to_camera) << " deg uncorrected, "
              << fixed_mm << " mm " << angle_deg(fixed.board_to_camera, s.board_to_camera)
              << " deg corrected\n";
    EXPECT_LT(fixed_mm, 0.01);
    EXPECT_LT(angle_deg(fixed.board_to_camera, s.board_to_camera), 0.001);
    EXPECT_GT(raw_mm, 10.0 * fixed_mm);
    EXPECT_NEAR(fixed.bias_px[0].norm(),
                (centroids[0] - est.project_circle(s.board_to_camera, 0).centre_px).norm(), 1e-3);
  }
}

TEST(BoardPoseEstimatorTest, PoseFromRenderedImagesAt60DegreesIsWithinAMillimetre) {
  const SyntheticScene s = testing::board_scene(1500.0, 60.0, 0.0, 0.0);
  const CircleFinder finder(s.board, s.camera);
  const CircleFinderResult found = finder.find(testing::noisy_frames(s, 10, 2.0, 100));
  ASSERT_TRUE(found.found) << found.problem;
  std::array<Eigen::Vector2d, 4> c;
  for (size_t i = 0; i < 4; ++i) c[i] = found.circles[i].centroid_px;
  const BoardPoseEstimator est(s.board, s.camera);
  const BoardPoseResult raw = est.estimate(c, {PnpMethod::kIppe, 0});
  const BoardPoseResult fixed = est.estimate(c, {PnpMethod::kIppe, 3});
  ASSERT_TRUE(raw.ok && fixed.ok);
  const double raw_mm = distance_mm(raw.board_to_camera, s.board_to_camera);
  const double fixed_mm = distance_mm(fixed.board_to_camera, s.board_to_camera);
  const double raw_deg = angle_deg(raw.board_to_camera, s.board_to_camera);
  const double fixed_deg = angle_deg(fixed.board_to_camera, s.board_to_camera);
  std::cout << "rendered, 60 deg, 10 frames noise 2: pose error " << raw_mm << " mm " << raw_deg
            << " deg uncorrected, " << fixed_mm << " mm " << fixed_deg << " deg corrected\n";
  EXPECT_LT(fixed_mm, 1.0);
  EXPECT_LT(fixed_deg, 0.1);
  EXPECT_GT(raw_mm, fixed_mm);
}

}  // namespace
}  // namespace ephor::catching
