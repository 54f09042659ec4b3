#pragma once
// The camera on RAMBO's tool plate, rendered (paper section 2, figure 1 top
// right: "synthetic images"): the target's faces that face the camera, filled
// and Lambert-shaded from a light along the camera's axis, so that its
// vertices show as corners where shades meet; a dark background; then blur
// and Gaussian noise. 8-bit grey, OpenCV camera frame (z forward).
#include <cstdint>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "common/rambo/image_triple.h"
#include "common/rambo/target_model.h"

namespace ephor::rambo {

// A link of whatever carries the target (the RM-501), drawn as a rod: a
// segment between two points and its radius, camera frame, mm.
struct RenderedLink {
  Eigen::Vector3d a_mm = Eigen::Vector3d::Zero();
  Eigen::Vector3d b_mm = Eigen::Vector3d::Zero();
  double radius_mm = 0.0;
};

class TargetRenderer {
 public:
  TargetRenderer(TargetModel model, CameraIntrinsics camera, double noise_grey = 3.0,
                 std::uint64_t seed = 1);
  // Renders the target at target_in_camera (mm) into `image` (CV_8UC1,
  // reallocated to the camera's size). Returns the number of faces drawn.
  // links: the carrying arm's links (camera frame), drawn first as flat grey
  // rods of their projected width, so the target hides them where it is in
  // front (painter's order: the RM-501 stands beyond the target as the
  // PUMA's camera sees it; a link in front of the target would wrongly be
  // hidden). A link with an end less than 10 mm in front of the camera is
  // left out.
  int render(const Eigen::Isometry3d& target_in_camera, cv::Mat& image,
             const std::vector<RenderedLink>& links = {});

 private:
  TargetModel model_;
  CameraIntrinsics camera_;
  double noise_grey_;
  cv::RNG rng_;  // the noise, seeded
};

}  // namespace ephor::rambo
