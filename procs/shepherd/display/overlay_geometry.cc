#include "procs/shepherd/display/overlay_geometry.h"

#include <cmath>
#include <numbers>
#include <stdexcept>

#include <Eigen/LU>

namespace ephor::display {

OverlayGeometry::OverlayGeometry(const calibration::AffineMap& image_to_table,
                                 double field_length_mm, double field_width_mm) {
  if (!image_to_table.allFinite()) throw std::invalid_argument("table-top map is not finite");
  if (!(field_length_mm > 0.0) || !(field_width_mm > 0.0)) {
    throw std::invalid_argument("field size must be > 0 mm");
  }
  const Eigen::Matrix2d linear = image_to_table.leftCols<2>();
  const double det = linear.determinant();
  if (!std::isfinite(det) || std::abs(det) < 1e-12) {
    throw std::invalid_argument("table-top map is singular");
  }
  inverse_ = linear.inverse();
  offset_ = image_to_table.col(2);
  px_per_mm_ = 1.0 / std::sqrt(std::abs(det));
  boundary_ = {field_to_image(0.0, 0.0), field_to_image(field_length_mm, 0.0),
               field_to_image(field_length_mm, field_width_mm),
               field_to_image(0.0, field_width_mm)};
}

double OverlayGeometry::blob_radius_px(double area_px) {
  if (!(area_px > 0.0)) return 0.0;
  return std::sqrt(area_px / std::numbers::pi);
}

std::vector<ImagePoint> OverlayGeometry::predicted_path(double u, double v, double vu_px_s,
                                                        double vv_px_s, double horizon_s,
                                                        int steps) {
  std::vector<ImagePoint> path;
  if (steps < 1 || !(horizon_s > 0.0)) return {{u, v}};
  path.reserve(static_cast<size_t>(steps) + 1);
  for (int i = 0; i <= steps; ++i) {
    const double t = horizon_s * i / steps;
    path.push_back({u + vu_px_s * t, v + vv_px_s * t});
  }
  return path;
}

ImagePoint OverlayGeometry::field_to_image(double x_mm, double y_mm) const {
  const Eigen::Vector2d uv = inverse_ * (Eigen::Vector2d(x_mm, y_mm) - offset_);
  return {uv.x(), uv.y()};
}

}  // namespace ephor::display
