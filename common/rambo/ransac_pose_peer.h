#pragma once
// The pose peer the issue asks ours to be compared with (RAMBO paper, section
// 5's task without its triangle pairs): OpenCV's solvePnPRansac (AP3P minimal
// sets, 3 px inlier threshold, 20 000 iterations at most) over every
// correspondence hypothesis, i.e. every distinct image point of a frame's
// triples paired with every model vertex. Used by ephor-bench-rambo and, on
// some frames, by ephor-rambo-pose in a live run, so that both figures come
// from the same frames.
#include <optional>
#include <vector>

#include <Eigen/Geometry>

#include "common/rambo/image_triple.h"
#include "common/rambo/target_model.h"

namespace ephor::rambo {

struct PeerPose {
  Eigen::Isometry3d target_in_camera = Eigen::Isometry3d::Identity();  // mm
  int inliers = 0;     // point-vertex pairs within the threshold
  int hypotheses = 0;  // point-vertex pairs tried (points x vertices)
};

class RansacPosePeer {
 public:
  RansacPosePeer(TargetModel model, CameraIntrinsics camera);

  // The target's pose in the camera frame, or nothing when RANSAC finds no
  // consensus (or the triples hold fewer than 4 distinct points). Pixels as
  // in ImageTriple.
  std::optional<PeerPose> estimate(const std::vector<ImageTriple>& triples) const;

 private:
  TargetModel model_;
  CameraIntrinsics camera_;
};

}  // namespace ephor::rambo
