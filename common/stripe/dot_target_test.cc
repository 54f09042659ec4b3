#include "common/stripe/dot_target.h"

#include <numbers>

#include <gtest/gtest.h>

#include "common/stripe/sensor_calibrator.h"
#include "common/stripe/stripe_renderer.h"

namespace ephor::stripe {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

struct Rendered {
  DotTarget target;
  StripeScene table;
  StripeRendererOptions options;
  CameraIntrinsics camera = CameraIntrinsics::paper_camera();

  Rendered() {
    options.dots_mm = target.dots_in_table();
    options.dot_radii_mm = target.dot_radii_mm();
  }
  cv::Mat image(const Eigen::Isometry3d& camera_in_table, bool dots = true) const {
    StripeRendererOptions o = options;
    if (!dots) {
      o.dots_mm.clear();
      o.dot_radii_mm.clear();
    }
    return StripeRenderer(table, camera, o).render_ambient(camera_in_table, 7);
  }
};

// A tilted, rolled view (image noise on): every dot found in the layout's
// order whatever the roll, and the PnP pose of the target is the true one.
TEST(DotTargetTest, FindsTheDotsInOrderAndTheTargetsPose) {
  const Rendered r;
  for (double roll_deg : {0.0, 90.0, 180.0, 250.0}) {
    const Eigen::Vector3d eye(-120.0, 40.0, 280.0), at(10.0, 20.0, 0.0);
    const Eigen::Isometry3d cam =
        look_at(eye, at, Eigen::Vector3d(std::cos(roll_deg * kDeg), std::sin(roll_deg * kDeg), 0));
    const auto s = r.target.find(r.image(cam), r.camera);
    ASSERT_TRUE(s) << "roll " << roll_deg;
    const Eigen::Isometry3d truth = cam.inverse() * r.target.target_in_table();
    EXPECT_LT((s->target_in_camera.translation() - truth.translation()).norm(), 0.3)
        << "roll " << roll_deg;
    EXPECT_LT(
        Eigen::AngleAxisd(s->target_in_camera.linear().transpose() * truth.linear()).angle() / kDeg,
        0.1)
        << "roll " << roll_deg;
    EXPECT_LT(s->rms_px, 0.2);
    const auto dots = r.target.dots_in_table();
    for (size_t i = 0; i < dots.size(); ++i) {
      const Eigen::Vector2d want =
          r.camera.project(cam.inverse() * Eigen::Vector3d(dots[i].x(), dots[i].y(), 0.0));
      EXPECT_LT((s->dots_px[i] - want).norm(), 0.3) << "dot " << i << " roll " << roll_deg;
    }
  }
}

// The dots leave the spot's sighting as it was (they stay out of the box
// its centroid is weighed over), and a view that cuts off part of the grid
// gives no target.
TEST(DotTargetTest, LeavesTheSpotAloneAndNeedsEveryDot) {
  const Rendered r;
  const Eigen::Isometry3d cam =
      look_at(Eigen::Vector3d(30, -40, 300), Eigen::Vector3d(0, 0, 0), Eigen::Vector3d::UnitY());
  const auto with = find_spot(r.image(cam)), without = find_spot(r.image(cam, false));
  ASSERT_TRUE(with && without);
  EXPECT_EQ(*with, *without);
  const Eigen::Isometry3d off =
      look_at(Eigen::Vector3d(0, -30, 250), Eigen::Vector3d(0, -30, 0), Eigen::Vector3d::UnitY());
  const cv::Mat image = r.image(off);
  EXPECT_TRUE(find_spot(image));
  EXPECT_FALSE(r.target.find(image, r.camera));
}

}  // namespace
}  // namespace ephor::stripe
