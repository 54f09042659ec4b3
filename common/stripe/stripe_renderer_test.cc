#include "common/stripe/stripe_renderer.h"

#include <gtest/gtest.h>

#include "common/stripe/stripe_extractor.h"

namespace ephor::stripe {
namespace {

// Flange straight down (z6 = -z of the table) at (0, 0, height): the drawing
// cage's projector is 80 mm below it looking down, its light plane x = 0.
Eigen::Isometry3d flange_down(double height_mm) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = Eigen::Vector3d(1, -1, -1).asDiagonal();
  t.translation() = Eigen::Vector3d(0, 0, height_mm);
  return t;
}

StripeScene plate_scene() {
  return StripeScene(
      parse_obj("v -150 -150 0\nv 150 -150 0\nv 150 150 0\nv -150 150 0\n"
                "v -150 -150 20\nv 150 -150 20\nv 150 150 20\nv -150 150 20\n"
                "f 5 6 7 8\nf 1 4 3 2\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n",
                "plate"));
}

// The plate's top (z = 20) 300 mm below the projector: the camera's principal
// ray meets the light plane there, so the stripe (the line x = 0, z = 20,
// parallel to the image's y axis) is the vertical image line u = cx = 127.5.
// 20 mm nearer, it moves to the projection of (0, 0, 20) from the raised
// camera (hand formula below).
TEST(StripeRendererTest, FlatPlateGivesAStraightStripeWhereTheGeometrySaysSo) {
  const StripeScene scene = plate_scene();
  const SensorCalibration cage = SensorCalibration::drawing_cage();
  StripeRendererOptions o;
  o.noise_sigma_grey = 0.0;
  const StripeRenderer renderer(scene, cage.camera, o);
  for (double height : {400.0, 380.0}) {
    const Eigen::Isometry3d t = flange_down(height);
    const Eigen::Isometry3d c = t * cage.camera_in_flange, s = t * cage.projector_in_flange;
    const cv::Mat img = renderer.render(c, s, 1);
    // Camera at (120, 0, height - 60) looking at (0, 0, height - 380): the
    // point (0, 0, 20) in camera coordinates.
    const Eigen::Vector3d pc = c.inverse() * Eigen::Vector3d(0, 0, 20);
    const double expected_u = cage.camera.project(pc).x();
    if (height == 400.0) {
      EXPECT_NEAR(expected_u, 127.5, 1e-9);
    }
    for (CentreMethod m : {CentreMethod::kGaussian, CentreMethod::kSteger}) {
      StripeExtractorOptions eo;
      eo.method = m;
      const Stripe stripe = StripeExtractor(eo).extract(img);
      ASSERT_EQ(stripe.points.size(), 256u) << "height " << height;
      double worst = 0.0;
      for (const StripePoint& p : stripe.points)
        worst = std::max(worst, std::abs(p.u_px - expected_u));
      EXPECT_LT(worst, 0.05) << centre_method_name(m) << " height " << height;
    }
  }
}

TEST(StripeRendererTest, PointsInTheLasersShadowAreNotLit) {
  // A 100 mm tall box at y in [10, 30] stands in the light plane x = 0 under
  // the projector at (0, 0, 320): the fan ray to the table point (0, 40, 0)
  // passes y = 27.5 at z = 100, through the box; the ray to (0, 60, 0) passes
  // y = 41 there, clear of it.
  const StripeScene scene(
      parse_obj("v -20 10 0\nv 20 10 0\nv 20 30 0\nv -20 30 0\n"
                "v -20 10 100\nv 20 10 100\nv 20 30 100\nv -20 30 100\n"
                "f 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n",
                "box"));
  const SensorCalibration cage = SensorCalibration::drawing_cage();
  const StripeRenderer renderer(scene, cage.camera);
  const Eigen::Isometry3d s = flange_down(400.0) * cage.projector_in_flange;
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  EXPECT_EQ(renderer.irradiance(s, {0, 40, 0}, up), 0.0);
  EXPECT_GT(renderer.irradiance(s, {0, 60, 0}, up), 0.5);
  EXPECT_GT(renderer.irradiance(s, {0, -40, 0}, up), 0.5);
  // The box's top is lit; beyond the fan (|y| > 320 tan(18.4 deg)) nothing is.
  EXPECT_GT(renderer.irradiance(s, {0, 20, 100}, up), 0.5);
  EXPECT_EQ(renderer.irradiance(s, {0, 120, 0}, up), 0.0);
  // Facing away from the projector: unlit.
  EXPECT_EQ(renderer.irradiance(s, {0, -40, 0}, -up), 0.0);
}

TEST(StripeRendererTest, SameSeedSameImage) {
  const StripeScene scene = plate_scene();
  const SensorCalibration cage = SensorCalibration::drawing_cage();
  const StripeRenderer renderer(scene, cage.camera);
  const Eigen::Isometry3d t = flange_down(400.0);
  const cv::Mat a = renderer.render(t * cage.camera_in_flange, t * cage.projector_in_flange, 5);
  const cv::Mat b = renderer.render(t * cage.camera_in_flange, t * cage.projector_in_flange, 5);
  const cv::Mat c = renderer.render(t * cage.camera_in_flange, t * cage.projector_in_flange, 6);
  EXPECT_EQ(cv::norm(a, b, cv::NORM_INF), 0.0);
  EXPECT_GT(cv::norm(a, c, cv::NORM_INF), 0.0);
  // Infrared-filter look: dark background, bright stripe.
  double lo = 0, hi = 0;
  cv::minMaxLoc(a, &lo, &hi);
  EXPECT_LT(lo, 10.0);
  EXPECT_GT(hi, 150.0);
}

}  // namespace
}  // namespace ephor::stripe
