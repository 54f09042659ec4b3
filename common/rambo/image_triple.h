#pragma once
// Image triples (RAMBO paper, section 4): a corner found in the image (the
// reference vertex) with two corners joined to it by image edges, the input
// of pose estimation. Pixel coordinates, origin at the top-left pixel's
// centre, x right, y down; the camera frame is OpenCV's (z forward).

#include <random>
#include <vector>

#include <Eigen/Geometry>

#include "common/rambo/target_model.h"

namespace ephor::rambo {

struct CameraIntrinsics {
  double fx_px = 800.0, fy_px = 800.0;  // focal lengths, px
  double cx_px = 320.0, cy_px = 240.0;  // principal point, px
  int width_px = 640, height_px = 480;

  Eigen::Vector2d project(const Eigen::Vector3d& p_camera_mm) const {
    return {fx_px * p_camera_mm.x() / p_camera_mm.z() + cx_px,
            fy_px * p_camera_mm.y() / p_camera_mm.z() + cy_px};
  }
  // The ray through a pixel, as (x, y, 1) in the camera frame.
  Eigen::Vector3d ray(const Eigen::Vector2d& px) const {
    return {(px.x() - cx_px) / fx_px, (px.y() - cy_px) / fy_px, 1.0};
  }
  bool valid() const;
};

struct ImageTriple {
  Eigen::Vector2d reference_px = Eigen::Vector2d::Zero();
  Eigen::Vector2d a_px = Eigen::Vector2d::Zero();  // joined to the reference
  Eigen::Vector2d b_px = Eigen::Vector2d::Zero();  // joined to the reference
  // Model vertices the reference could be (e.g. from tracking or a
  // distinctive corner); empty: any.
  std::vector<int> reference_candidates;
};

// What the features stage would find in a perfect rendering: every visible
// vertex of `model` at `target_in_camera` (mm) projected with Gaussian
// pixel noise (noise_px per axis, same noise for a vertex in all its
// triples), and a triple for each visible vertex and each pair of visible
// edges at it. Vertices behind the camera or outside the image are dropped.
std::vector<ImageTriple> synthetic_image_triples(const TargetModel& model,
                                                 const CameraIntrinsics& camera,
                                                 const Eigen::Isometry3d& target_in_camera,
                                                 double noise_px, std::mt19937* rng);

}  // namespace ephor::rambo
