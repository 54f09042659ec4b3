#include "common/rambo/target_renderer.h"

#include <gtest/gtest.h>

#include "common/rambo/rambo_cell.h"

namespace ephor::rambo {
namespace {

TEST(TargetRenderer, DrawsShadedFacesWhereTheTargetProjects) {
  const RamboCell cell = RamboCell::make(4);
  TargetRenderer r(cell.model, cell.camera, 2.0, 7);
  Eigen::Isometry3d in_camera = Eigen::Isometry3d::Identity();
  in_camera.linear() = Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 1, 0).normalized()).matrix();
  in_camera.translation() = Eigen::Vector3d(0, 0, 600);
  cv::Mat image;
  const int faces = r.render(in_camera, image);
  EXPECT_GE(faces, 2);
  EXPECT_LE(faces, 5);
  ASSERT_EQ(image.cols, 640);
  ASSERT_EQ(image.rows, 480);
  // Centre of the target bright, a corner of the image background.
  EXPECT_GT(image.at<uint8_t>(240, 320), 60);
  EXPECT_LT(image.at<uint8_t>(5, 5), 50);
  // Behind the camera: nothing drawn.
  in_camera.translation() = Eigen::Vector3d(0, 0, -600);
  EXPECT_EQ(r.render(in_camera, image), 0);
}

// The carrying arm's links: a rod beyond the target shows grey where the
// target does not hide it, and the target's faces are drawn over it.
TEST(TargetRenderer, DrawsTheCarryingArmsLinksBehindTheTarget) {
  const RamboCell cell = RamboCell::make(4);
  TargetRenderer r(cell.model, cell.camera, 0.0, 7);
  Eigen::Isometry3d in_camera = Eigen::Isometry3d::Identity();
  in_camera.translation() = Eigen::Vector3d(0, 0, 600);
  cv::Mat plain, with_arm;
  r.render(in_camera, plain);
  // A level rod 40 mm in radius from the image's centre to its right edge,
  // 300 mm beyond the target's centre (column 320 + 380 * 600 / 900 = 573
  // at its right end).
  const std::vector<RenderedLink> rod{
      {Eigen::Vector3d(0, 0, 900), Eigen::Vector3d(600, 0, 900), 40.0}};
  r.render(in_camera, with_arm, rod);
  // Where the target is, it hides the rod: the same pixels.
  EXPECT_EQ(with_arm.at<uint8_t>(240, 320), plain.at<uint8_t>(240, 320));
  // Beside the target (its right face ends near column 320 + 380 * 120 /
  // 600 = 396), the rod's grey over the background.
  EXPECT_LT(plain.at<uint8_t>(240, 500), 40);
  EXPECT_NEAR(with_arm.at<uint8_t>(240, 500), 95, 3);
  // The rod is about 2 * 40 * 380 / 900 = 34 px wide: 25 px off its line, background.
  EXPECT_LT(with_arm.at<uint8_t>(265, 500), 40);
  // A rod reaching behind the camera is left out, not drawn wrapped round.
  const std::vector<RenderedLink> behind{
      {Eigen::Vector3d(0, 0, 900), Eigen::Vector3d(600, 0, -100), 40.0}};
  r.render(in_camera, with_arm, behind);
  EXPECT_LT(with_arm.at<uint8_t>(240, 500), 40);
}

}  // namespace
}  // namespace ephor::rambo
