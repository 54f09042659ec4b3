#pragma once
// The camera on RAMBO's tool plate, rendered (paper section 2, figure 1 top
// right: "synthetic images"): the target's faces that face the camera, filled
// and Lambert-shaded from a light along the camera's axis, so that its
// vertices show as corners where shades meet; a dark background; then blur
// and Gaussian noise. 8-bit grey, OpenCV camera frame (z forward).
#include <cstdint>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "common/rambo/image_triple.h"
#include "common/rambo/target_model.h"

namespace ephor::rambo {

class TargetRenderer {
 public:
  TargetRenderer(TargetModel model, CameraIntrinsics camera, double noise_grey = 3.0,
                 std::uint64_t seed = 1);
  // Renders the target at target_in_camera (mm) into `image` (CV_8UC1,
  // reallocated to the camera's size). Returns the number of faces drawn.
  int render(const Eigen::Isometry3d& target_in_camera, cv::Mat& image);

 private:
  TargetModel model_;
  CameraIntrinsics camera_;
  double noise_grey_;
  cv::RNG rng_;  // the noise, seeded
};

}  // namespace ephor::rambo
