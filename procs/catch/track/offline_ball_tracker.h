#pragma once
// OfflineBallTracker: the catching system's perception (paper 000,
// sections 3-5.4) run offline over a recorded video of a real board, for
// `tools/ephor catch track`. The same algorithms as the live processes, in
// the same order, without LCM or a clock:
// - initialisation (ephor-catch-vision at start-up): the four circles over
//   a few frames of the still board (CircleFinder, automatically or in the
//   operator's windows), their perspective-corrected centroids, the board's
//   pose by IPPE with both solutions checked (BoardPoseEstimator);
// - vision (ephor-catch-vision per frame): frame differencing 1/30 s apart
//   (n and n-2 at 60 fps), threshold, moments, the crescent correction
//   (MotionCentroid), inside the window of interest around the previous
//   frame's estimate (BallWindow);
// - world model (ephor-catch-worldmodel per frame): the ray to the board
//   plane raised by the ball's radius, the paper's filters, the Kalman
//   filter (BallWorldModel).
//
// A frame's time is its index / fps (s, from 0). The board's incline is not
// seen by the camera; it sets the rolling acceleration (5/7 g sin i) of the
// Kalman filter and the jump filter's limit, so it is an option.
//
// Frames are 8-bit grey of the camera file's size (to_grey converts what a
// video decoder gives). Not thread-safe; one caller feeds frames in order.

#include <array>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "common/catch/board_model.h"
#include "common/catch/vision/ball_window.h"
#include "common/catch/vision/board_pose_estimator.h"
#include "common/catch/vision/circle_finder.h"
#include "common/catch/vision/motion_centroid.h"
#include "common/catch/worldmodel/ball_world_model.h"

namespace ephor::catching {

struct OfflineTrackerOptions {
  double fps = 60.0;  // frames per second of the recording
  // The operator's windows around the four circles (board order); none: found automatically.
  std::optional<std::array<cv::Rect, 4>> circle_windows;
  double incline_deg = 25.0;  // the board's incline (the simulator draws 15-35 deg)
  bool use_window = true;     // false: search the whole image every frame (the paper's way)
  double window_margin_px = 24.0;
  // A new ball is acquired only above this y of B (mm); infinity = anywhere.
  double acquire_max_y_mm = std::numeric_limits<double>::infinity();
};

struct TrackerInitialisation {
  bool ok = false;
  std::string problem;  // why not ok: which circle, where it was looked for, or the pose's reason
  CircleFinderResult circles;
  BoardPoseResult pose;
};

struct TrackedFrame {
  int frame = 0;     // index from 0
  double t_s = 0.0;  // frame / fps
  BallStatus status = BallStatus::kNoBall;
  RejectReason reason = RejectReason::kNone;
  // The ball's centre in B (x, y; mm), filtered, while a ball is tracked on
  // the board (TRACKING, or REJECTED while the track coasts); none otherwise.
  std::optional<Eigen::Vector2d> ball_b_mm;
  std::optional<Eigen::Vector2d> centroid_px;  // the vision's ball centre, if it found one
  std::optional<cv::Rect> window;              // where the vision looked; none = whole image
};

class OfflineBallTracker {
 public:
  // Throws std::invalid_argument for a non-positive fps or margin or an
  // incline outside (0, 90) deg.
  OfflineBallTracker(const BoardSpec& board, const CameraIntrinsics& camera,
                     OfflineTrackerOptions options);

  // The board's pose from these frames of the still board (8-bit grey, the
  // camera's size). On success the tracker is ready for track(); a failed
  // attempt may be repeated with other frames.
  TrackerInitialisation initialise(const std::vector<cv::Mat>& frames);
  bool initialised() const { return model_.has_value(); }
  const BoardPoseResult& pose() const { return pose_; }

  // The next frame of the recording (frame 0 first). Throws std::logic_error
  // before a successful initialise(), std::invalid_argument for a frame that
  // is not 8-bit grey of the camera's size.
  TrackedFrame track(const cv::Mat& frame);

  // How many frames 1/30 s is at this fps (at least 1): the differencing gap.
  int frame_gap() const { return frame_gap_; }

 private:
  BoardSpec board_;
  CameraIntrinsics camera_;
  OfflineTrackerOptions options_;
  int frame_gap_ = 2;
  BoardPoseResult pose_;
  MotionCentroid motion_;
  std::optional<BallWindow> window_;
  std::optional<BallWorldModel> model_;
  int next_frame_ = 0;
};

// An 8-bit grey copy (or view) of a decoded frame: grey as is, BGR / BGRA
// converted. Throws std::invalid_argument naming the frame's depth or
// channels when it is neither (e.g. 16-bit).
cv::Mat to_grey(const cv::Mat& decoded);

}  // namespace ephor::catching
