#include "procs/stripe/planner/scan_sequencer.h"

#include <spdlog/fmt/fmt.h>

namespace ephor::stripe {

const char* to_string(ScanState s) {
  switch (s) {
    case ScanState::kWaiting:
      return "waiting";
    case ScanState::kRunning:
      return "running";
    case ScanState::kCaptured:
      return "captured";
    case ScanState::kDone:
      return "done";
    case ScanState::kFailed:
      return "failed";
  }
  return "unknown";
}

ScanSequencer::ScanSequencer(std::vector<arm::Joints> goals, int64_t first_goal_id,
                             int64_t first_request_id, SequencerConfig config)
    : goals_(std::move(goals)),
      config_(config),
      next_goal_id_(first_goal_id),
      next_request_id_(first_request_id) {}

SequencerActions ScanSequencer::fail(const std::string& why) {
  state_ = ScanState::kFailed;
  phase_ = Phase::kNone;
  reason_ = why;
  SequencerActions a;
  a.changed = true;
  return a;
}

SequencerActions ScanSequencer::start(double now_s) {
  if (state_ != ScanState::kWaiting || phase_ != Phase::kNone) return {};
  phase_ = Phase::kProbe;
  stripe_ = -1;
  return capture(now_s, false);
}

SequencerActions ScanSequencer::capture(double now_s, bool repeat) {
  if (!repeat) {
    request_id_ = next_request_id_++;
    attempts_ = 0;
  }
  ++attempts_;
  request_sent_s_ = now_s;
  SequencerActions a;
  a.capture = CaptureAction{request_id_, stripe_};
  return a;
}

SequencerActions ScanSequencer::send_goal(double now_s) {
  // The next stripe, or the end of the raster.
  if (stripe_ >= planned()) {
    state_ = ScanState::kCaptured;
    phase_ = Phase::kCloud;
    phase_since_s_ = now_s;
    SequencerActions a;
    a.changed = true;
    return a;
  }
  phase_ = Phase::kMoving;
  phase_since_s_ = now_s;
  if (first_goal_s_ < 0) first_goal_s_ = now_s;
  goal_id_ = next_goal_id_++;
  SequencerActions a;
  a.goal = GoalAction{goal_id_, stripe_, goals_[static_cast<size_t>(stripe_)]};
  return a;
}

SequencerActions ScanSequencer::on_image(int64_t request_id, int64_t image_index, double now_s) {
  if (request_id != request_id_) return {};  // someone else's, or a repeat's second answer
  if (phase_ == Phase::kProbe) {
    probe_image_ = image_index;
    phase_ = Phase::kProbeImaged;
    return {};
  }
  if (phase_ != Phase::kCapturing) return {};
  ++captured_;
  if (first_image_s_ < 0) first_image_s_ = now_s;
  last_image_s_ = now_s;
  ++stripe_;
  SequencerActions a = send_goal(now_s);  // the arm moves on while this image is processed
  a.changed = true;
  return a;
}

SequencerActions ScanSequencer::on_points(int64_t image_index, double now_s) {
  if (phase_ != Phase::kProbeImaged || image_index != probe_image_) return {};
  state_ = ScanState::kRunning;
  stripe_ = 0;
  SequencerActions a = send_goal(now_s);
  a.changed = true;
  return a;
}

SequencerActions ScanSequencer::on_motion_done(int64_t goal_id, int status,
                                               const std::string& reason, double now_s) {
  if (phase_ != Phase::kMoving || goal_id != goal_id_) return {};
  motion_s_ += now_s - phase_since_s_;
  switch (status) {
    case 0:  // done: the arm is at rest there
      phase_ = Phase::kCapturing;
      return capture(now_s, false);
    case 1: {  // rejected: skip the stripe
      ++skipped_;
      ++stripe_;
      SequencerActions a = send_goal(now_s);
      a.changed = true;
      return a;
    }
    default:
      return fail(fmt::format("stripe {}: the arm {} the move: {}", stripe_,
                              status == 2 ? "failed" : "timed out on", reason));
  }
}

SequencerActions ScanSequencer::on_cloud(int64_t points, double now_s) {
  if (phase_ != Phase::kCloud) return {};
  state_ = ScanState::kDone;
  phase_ = Phase::kNone;
  cloud_points_ = points;
  done_s_ = now_s;
  SequencerActions a;
  a.changed = true;
  return a;
}

SequencerActions ScanSequencer::tick(double now_s) {
  switch (phase_) {
    case Phase::kProbe:
    case Phase::kProbeImaged:
    case Phase::kCapturing:
      if (now_s - request_sent_s_ < config_.capture_timeout_s) return {};
      if (attempts_ >= config_.capture_attempts)
        return fail(phase_ == Phase::kCapturing
                        ? fmt::format("stripe {}: no image from the camera after {} requests",
                                      stripe_, attempts_)
                        : fmt::format("the probe image did not come back through the camera, "
                                      "stripe and range processes in {} tries ({})",
                                      attempts_,
                                      phase_ == Phase::kProbe ? "no image"
                                                              : "the image came, its points not"));
      // Asked again with the same id: the camera answers a repeat with the
      // same image, which the stripe and range processes then handle again.
      return capture(now_s, true);
    case Phase::kMoving:
      if (now_s - phase_since_s_ > config_.motion_timeout_s)
        return fail(fmt::format("stripe {}: no MOTION_DONE for goal {} in {:.0f} s", stripe_,
                                goal_id_, config_.motion_timeout_s));
      return {};
    case Phase::kCloud:
      if (now_s - phase_since_s_ > config_.cloud_timeout_s)
        return fail(
            fmt::format("no complete cloud from the range process {:.0f} s after the "
                        "last image",
                        config_.cloud_timeout_s));
      return {};
    case Phase::kNone:
      return {};
  }
  return {};
}

double ScanSequencer::elapsed_s(double now_s) const {
  if (first_goal_s_ < 0) return 0.0;
  return (done_s_ >= 0 ? done_s_ : now_s) - first_goal_s_;
}

double ScanSequencer::stripes_per_s() const {
  if (captured_ < 2 || !(last_image_s_ > first_image_s_)) return 0.0;
  return (captured_ - 1) / (last_image_s_ - first_image_s_);
}

}  // namespace ephor::stripe
