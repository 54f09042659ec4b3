#pragma once
// Pinhole camera looking straight down on the field (the simulator's camera,
// and the true geometry the calibration approximates). Image frame: px,
// origin at the centre of the top-left pixel, u right, v down. Square pixels.
//
// Because it is a perspective camera, a point in the elevation plane appears
// farther from the image centre than the same (x, y) on the table: that is
// why the calibration needs a fourth point for the elevation plane
// (paper 003, equation 1).

#include <Eigen/Core>

namespace ephor::geometry {

struct OverheadCamera {
  int width_px = 512;
  int height_px = 482;
  double centre_x_mm = 609.5;  // optical centre above this point of F, mm
  double centre_y_mm = 457.0;
  double height_mm = 2500.0;  // camera height above the table, mm
  double focal_px = 906.0;    // fits the field, also seen in the elevation plane, into 512 px
  double cu_px = 255.5;       // principal point, px
  double cv_px = 240.5;

  // F (mm) -> image (px). Points at or above the camera are not valid.
  Eigen::Vector2d project(double x_mm, double y_mm, double z_mm) const {
    const double s = focal_px / (height_mm - z_mm);
    return {cu_px + s * (x_mm - centre_x_mm), cv_px - s * (y_mm - centre_y_mm)};
  }
  // Image (px) at height z_mm -> F (x, y) mm.
  Eigen::Vector2d unproject(double u_px, double v_px, double z_mm) const {
    const double s = (height_mm - z_mm) / focal_px;
    return {centre_x_mm + s * (u_px - cu_px), centre_y_mm - s * (v_px - cv_px)};
  }
  // Size in px of a length in mm lying at height z_mm.
  double px_per_mm(double z_mm) const { return focal_px / (height_mm - z_mm); }
};

}  // namespace ephor::geometry
