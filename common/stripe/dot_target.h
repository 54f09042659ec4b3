#pragma once
// A printed calibration target on the table for the hand-eye peer (issue
// 16: OpenCV's calibrateHandEye needs the target's pose in the camera
// frame in every view, which the single spot of section 4 cannot give):
// eight small dark dots around the spot on a 3 x 3 grid whose centre is the
// spot, seen in the same images (filter removed, laser off) as the spot, so
// the peer and the paper's procedures use the same views.
//
// Layout: the grid's columns along the table's +x, rows along +y, pitch_mm
// apart. The grid alone is symmetric under a quarter turn; the dot at
// (column 0, row 0), the table's -x, -y corner, is larger (the marker) and
// settles it (with the handedness every view from above the table has).
// The pitch keeps every dot outside the box find_spot weighs the spot's
// centroid over (the spot's 8 mm radius plus 2 px), so the spot's
// sightings are the same with or without the dots.
//
// Target frame: origin at the spot's centre, x along the columns, y along
// the rows, z up (the table's axes, moved). Units: mm, pixels.

#include <optional>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "common/stripe/sensor_model.h"

namespace ephor::stripe {

struct DotTargetLayout {
  double pitch_mm = 24.0;
  double dot_radius_mm = 2.5;
  double marker_radius_mm = 4.0;  // the dot at column 0, row 0
};

// One view of the target.
struct TargetSighting {
  std::vector<Eigen::Vector2d> dots_px;  // in the layout's order (dots_in_target)
  Eigen::Vector2d spot_px = Eigen::Vector2d::Zero();
  Eigen::Isometry3d target_in_camera = Eigen::Isometry3d::Identity();  // target -> camera (PnP)
  double rms_px = 0.0;  // the pose's reprojection error over the dots
};

class DotTarget {
 public:
  // The grid around the spot at spot_mm (table frame, on z = 0).
  explicit DotTarget(Eigen::Vector2d spot_mm = Eigen::Vector2d::Zero(),
                     DotTargetLayout layout = {});

  // Dot centres on the table (table frame, mm) and their radii, in the
  // layout's order: what the renderer draws (StripeRendererOptions).
  std::vector<Eigen::Vector2d> dots_in_table() const;
  std::vector<double> dot_radii_mm() const;
  // Dot centres in the target frame (mm, z = 0): row by row from row 0,
  // columns along +x, the centre (the spot) left out; the marker first.
  std::vector<Eigen::Vector3d> dots_in_target() const;
  // The target frame -> table frame.
  Eigen::Isometry3d target_in_table() const;

  // The target in an image taken with the filter removed: the spot (the
  // largest dark blob, find_spot), every dot's darkness-weighted centroid
  // (own centroids: the dots are too small for OpenCV's blob detector's
  // defaults), their order by cv::findCirclesGrid on those centroids and
  // the spot's, the turn settled by the marker (the next largest blob),
  // and the pose by cv::solvePnP with `camera` (no distortion) on the
  // eight dots. nullopt unless the spot and all the dots are in view, off
  // the border, ordered and the pose fits them within max_rms_px.
  std::optional<TargetSighting> find(const cv::Mat& image, const CameraIntrinsics& camera,
                                     int threshold = 100, double max_rms_px = 0.5) const;

  const DotTargetLayout& layout() const { return layout_; }

 private:
  Eigen::Vector2d spot_mm_;
  DotTargetLayout layout_;
};

}  // namespace ephor::stripe
