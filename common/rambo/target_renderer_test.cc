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

}  // namespace
}  // namespace ephor::rambo
