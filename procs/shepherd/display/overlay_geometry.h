#pragma once
// OverlayGeometry: what the page draws over the camera image, computed on the
// server so the page only draws: blob circles of the blob's area, predicted
// paths, the field boundary and the tool footprint. Image frame: px, u right,
// v down, origin at the centre of the top-left pixel (camera_frame_t).
//
// Immutable after construction; safe to share between threads.

#include <utility>
#include <vector>

#include <Eigen/Core>

#include "common/calibration/field_calibration.h"

namespace ephor::display {

struct ImagePoint {
  double u = 0.0;  // px
  double v = 0.0;  // px
};

class OverlayGeometry {
 public:
  // `image_to_table`: the image -> F map (mm) of the table top (z = 0), e.g.
  // FieldCalibration::matrix_at_height(0). Throws std::invalid_argument when
  // its linear part is singular or not finite, or a field size is not > 0.
  OverlayGeometry(const calibration::AffineMap& image_to_table, double field_length_mm,
                  double field_width_mm);

  // Radius (px) of the circle whose area equals `area_px` (the paper draws
  // each blob as a circle of the blob's area). 0 for area <= 0.
  static double blob_radius_px(double area_px);

  // Straight-line prediction from (u, v) with velocity (vu, vv) px/s:
  // `steps` + 1 points, 0 .. horizon_s seconds ahead.
  static std::vector<ImagePoint> predicted_path(double u, double v, double vu_px_s, double vv_px_s,
                                                double horizon_s, int steps);

  // The four field corners in the image, in order (0,0), (L,0), (L,W), (0,W).
  const std::vector<ImagePoint>& field_boundary() const { return boundary_; }

  // F (mm, table top) -> image (px).
  ImagePoint field_to_image(double x_mm, double y_mm) const;
  // Image px per mm on the table top (mean scale of the linear part).
  double px_per_mm() const { return px_per_mm_; }

 private:
  Eigen::Matrix2d inverse_;  // F -> image, linear part
  Eigen::Vector2d offset_;   // image -> F translation
  double px_per_mm_ = 1.0;
  std::vector<ImagePoint> boundary_;
};

}  // namespace ephor::display
