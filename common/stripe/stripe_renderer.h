#pragma once
// The camera's image of the light stripe, by ray casting (issue 16's
// simulated sensor): each pixel's ray meets the first surface of the scene;
// the pixel is lit when that point lies in the laser sheet, inside its fan,
// facing the projector, and in sight of the projector (not in a shadow). The
// infrared filter makes the rest dark: background, the stripe and noise.
//
// Photometry (why the numbers): the sheet's thickness profile is a Gaussian
// whose FWHM grows in proportion to the range (1 mm at 300 mm, section 2: the
// width is the emitter imaged by the cylindrical lens); a fan spread along its
// length and width in proportion to the range gives irradiance ~ 1/r^2;
// surfaces are Lambertian (x cos of the incidence angle). Each pixel averages
// the profile over its width across the stripe (the distance from the sheet
// is linear within a pixel on a flat face), so sub-pixel centres are real.

#include <cstdint>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "common/stripe/sensor_model.h"
#include "common/stripe/stripe_scene.h"

namespace ephor::stripe {

struct StripeRendererOptions {
  LaserSheet laser;
  double peak_grey = 200.0;       // sheet centre on a surface square to it at the reference range
  double background_grey = 8.0;   // the dark scene through the infrared filter
  double noise_sigma_grey = 2.0;  // per pixel, Gaussian, seeded per image

  // With the infrared filter removed and the laser off (section 4's camera
  // calibration): the table's contrasting spot, a dark disc on the light
  // table top, table frame mm.
  Eigen::Vector2d spot_centre_mm = Eigen::Vector2d::Zero();
  double spot_radius_mm = 8.0;
  double table_grey = 170.0;
  double spot_grey = 30.0;
  double object_grey = 120.0;  // objects, times the cosine of their slope
  // A printed calibration target around the spot (DotTarget, for the
  // hand-eye peer): dark discs at these centres (table frame, mm, on z = 0)
  // with these radii (mm), drawn like the spot. None by default.
  std::vector<Eigen::Vector2d> dots_mm;
  std::vector<double> dot_radii_mm;
};

class StripeRenderer {
 public:
  // `scene` must outlive the renderer.
  StripeRenderer(const StripeScene& scene, CameraIntrinsics camera,
                 StripeRendererOptions options = {});

  // camera_pose = C, projector_pose = S (frame -> table), mm. 8-bit image of
  // camera.height_px x camera.width_px. Same seed, same image.
  cv::Mat render(const Eigen::Isometry3d& camera_pose, const Eigen::Isometry3d& projector_pose,
                 std::uint64_t seed) const;

  // The view with the filter removed and the laser off: table, spot and
  // objects under diffuse light (no stripe), seeded noise.
  cv::Mat render_ambient(const Eigen::Isometry3d& camera_pose, std::uint64_t seed) const;

  // Fraction of the sheet's peak irradiance reaching point p (table frame) on
  // a surface with unit normal `normal`, ignoring the sheet's thickness
  // profile: 0 outside the fan, behind the projector, facing away or in a
  // shadow; else cos(incidence) (r_ref / r)^2.
  double irradiance(const Eigen::Isometry3d& projector_pose, const Eigen::Vector3d& p,
                    const Eigen::Vector3d& normal) const;

  // Sheet thickness (Gaussian sigma, mm) at range r from the projector.
  double sheet_sigma_mm(double range_mm) const;

  const CameraIntrinsics& camera() const { return camera_; }
  const StripeRendererOptions& options() const { return options_; }

 private:
  const StripeScene* scene_;
  CameraIntrinsics camera_;
  StripeRendererOptions options_;
};

}  // namespace ephor::stripe
