#pragma once
// BallWindow: the window of interest around where the ball is expected
// (paper 000, section 5.4 suggests it; the PIPE searched the whole image).
// Frame differencing sees the ball twice, where it is now and where it was
// in the differenced frame 1/30 s earlier, so the window covers both
// positions plus a margin for the prediction's error.
//
// Used by the vision process (the world model's newest estimate carried to
// the frame's capture time) and the offline tracker (the previous frame's
// estimate). Positions and velocities are the ball's centre in the board
// frame B (common/catch/board_model.h), mm and mm/s; the centre rolls at
// z_B = +ball radius. Immutable; safe to share between threads.

#include <optional>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "common/catch/board_model.h"
#include "common/catch/vision/board_pose_estimator.h"

namespace ephor::catching {

struct BallWindowOptions {
  double margin_px = 24.0;               // around both projected positions, px
  double difference_gap_s = 1.0 / 30.0;  // how far back the differenced frame is, s
  double max_ahead_s = 0.1;              // an estimate older than this gives no window
};

class BallWindow {
 public:
  // Throws std::invalid_argument for a non-positive margin or gap, or a
  // negative max_ahead_s.
  BallWindow(const BoardSpec& board, const CameraIntrinsics& camera, const Pose& board_to_camera,
             BallWindowOptions options = {});

  // The window (clipped to the image) for a frame captured `ahead_s` after
  // the estimate (position, velocity) was valid. nullopt (search the whole
  // image) when ahead_s is negative or beyond max_ahead_s, the estimate is
  // not finite, or the window falls outside the image.
  std::optional<cv::Rect> around(const Eigen::Vector2d& position_b_mm,
                                 const Eigen::Vector2d& velocity_b_mm_s, double ahead_s) const;

  const BallWindowOptions& options() const { return options_; }

 private:
  BoardPoseEstimator projector_;
  Pose board_to_camera_;
  BallWindowOptions options_;
};

}  // namespace ephor::catching
