#include "procs/catch/track/offline_ball_tracker.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include <opencv2/imgproc.hpp>

namespace ephor::catching {
namespace {

constexpr double kPi = 3.14159265358979323846;

MotionCentroidOptions motion_options(int frame_gap) {
  MotionCentroidOptions o;
  o.frame_gap = frame_gap;
  return o;
}

std::string size_text(int width, int height) {
  return std::to_string(width) + " x " + std::to_string(height);
}

}  // namespace

OfflineBallTracker::OfflineBallTracker(const BoardSpec& board, const CameraIntrinsics& camera,
                                       OfflineTrackerOptions options)
    : board_(board), camera_(camera), options_(std::move(options)) {
  if (!(options_.fps > 0.0) || !std::isfinite(options_.fps))
    throw std::invalid_argument("offline tracker: fps must be positive, got " +
                                std::to_string(options_.fps));
  if (!(options_.window_margin_px > 0.0))
    throw std::invalid_argument("offline tracker: window margin must be positive");
  if (!(options_.incline_deg > 0.0 && options_.incline_deg < 90.0))
    throw std::invalid_argument("offline tracker: incline must be in (0, 90) deg, got " +
                                std::to_string(options_.incline_deg));
  // The paper differenced frames 1/30 s apart (the same field parity at 60 Hz).
  frame_gap_ = std::max(1, static_cast<int>(std::lround(options_.fps / 30.0)));
  motion_ = MotionCentroid(motion_options(frame_gap_));
}

TrackerInitialisation OfflineBallTracker::initialise(const std::vector<cv::Mat>& frames) {
  CircleFinderOptions finder_options;
  finder_options.windows = options_.circle_windows;
  const CircleFinder finder(board_, camera_, finder_options);
  TrackerInitialisation out;
  out.circles = finder.find(frames);
  if (!out.circles.found) {
    out.problem = out.circles.problem;
    return out;
  }
  std::array<Eigen::Vector2d, 4> centroids;
  for (size_t k = 0; k < 4; ++k) centroids[k] = out.circles.circles[k].centroid_px;
  out.pose = BoardPoseEstimator(board_, camera_).estimate(centroids);
  if (!out.pose.ok) {
    out.problem = out.pose.problem;
    return out;
  }
  out.ok = true;
  pose_ = out.pose;
  BoardPlacement placement;
  placement.incline_rad = options_.incline_deg * kPi / 180.0;
  BallWorldModelParams params;
  params.acquire_max_y_mm = options_.acquire_max_y_mm;
  model_.emplace(board_, placement, camera_, pose_.board_to_camera, params);
  window_.emplace(board_, camera_, pose_.board_to_camera,
                  BallWindowOptions{options_.window_margin_px, frame_gap_ / options_.fps,
                                    // an estimate a few frames old still places the window
                                    std::max(0.1, 3.0 / options_.fps)});
  // The ball's image radius from the pose (at the board's centre; within
  // ~15 % elsewhere on a board in view): the crescent correction needs it,
  // and learning it waits for the ball to move a diameter in 1/30 s, so the
  // first ~0.2 s of each roll would lag by half the displacement.
  MotionCentroidOptions motion_options_known = motion_options(frame_gap_);
  const Eigen::Vector3d centre_c =
      pose_.board_to_camera *
      Eigen::Vector3d(board_.width_mm / 2.0, board_.height_mm / 2.0, board_.ball_radius_mm());
  motion_options_known.ball_radius_px =
      0.5 * (camera_.fx + camera_.fy) * board_.ball_radius_mm() / centre_c.z();
  motion_ = MotionCentroid(motion_options_known);
  next_frame_ = 0;
  return out;
}

TrackedFrame OfflineBallTracker::track(const cv::Mat& frame) {
  if (!model_) throw std::logic_error("offline tracker: track() before a successful initialise()");
  if (frame.type() != CV_8UC1 || frame.cols != camera_.width || frame.rows != camera_.height)
    throw std::invalid_argument("offline tracker: frame " + std::to_string(next_frame_) + " is " +
                                size_text(frame.cols, frame.rows) +
                                (frame.type() == CV_8UC1 ? "" : " (not 8-bit grey)") +
                                "; the camera is " + size_text(camera_.width, camera_.height));
  TrackedFrame out;
  out.frame = next_frame_++;
  out.t_s = out.frame / options_.fps;
  const int64_t utime = static_cast<int64_t>(std::llround(out.t_s * 1e6));

  // The window around the previous frame's estimate carried to this frame.
  const BallFrame& previous = model_->last();
  if (options_.use_window && model_->frames() > 0 && previous.has_state &&
      previous.status == BallStatus::kTracking)
    out.window = window_->around(previous.position_b_mm, previous.velocity_b_mm_s,
                                 static_cast<double>(utime - previous.utime) / 1e6);

  const MotionMeasurement m = motion_.process(frame, out.window);
  std::optional<Eigen::Vector2d> centroid;
  if (m.found && m.centroid_px.allFinite()) centroid = m.centroid_px;
  out.centroid_px = centroid;

  const BallFrame& f = model_->update(utime, centroid);
  out.status = f.status;
  out.reason = f.reason;
  if (f.has_state && (f.status == BallStatus::kTracking || f.status == BallStatus::kRejected))
    out.ball_b_mm = f.position_b_mm;
  return out;
}

cv::Mat to_grey(const cv::Mat& decoded) {
  if (decoded.empty()) throw std::invalid_argument("empty frame");
  if (decoded.depth() != CV_8U)
    throw std::invalid_argument("frame is not 8 bits per channel (OpenCV depth " +
                                std::to_string(decoded.depth()) + "); want 8-bit grey or colour");
  switch (decoded.channels()) {
    case 1:
      return decoded;
    case 3: {
      cv::Mat grey;
      cv::cvtColor(decoded, grey, cv::COLOR_BGR2GRAY);
      return grey;
    }
    case 4: {
      cv::Mat grey;
      cv::cvtColor(decoded, grey, cv::COLOR_BGRA2GRAY);
      return grey;
    }
    default:
      throw std::invalid_argument("frame has " + std::to_string(decoded.channels()) +
                                  " channels; want 1 (grey), 3 or 4 (colour)");
  }
}

}  // namespace ephor::catching
