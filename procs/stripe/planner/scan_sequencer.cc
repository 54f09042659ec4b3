#include "procs/stripe/planner/scan_sequencer.h"

#include <algorithm>

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
      next_request_id_(first_request_id) {
  for (int i = 0; i < planned(); ++i) order_.push_back(i);
}

int ScanSequencer::skipped() const {
  int n = 0;
  for (const int i : refused_) n += imaged_.count(i) == 0 ? 1 : 0;
  return n;
}

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
  phase_ = Phase::kMoving;
  phase_since_s_ = now_s;
  if (first_goal_s_ < 0) first_goal_s_ = now_s;
  goal_id_ = next_goal_id_++;
  ++goal_sends_;
  SequencerActions a;
  a.goal = GoalAction{goal_id_, stripe_, goals_[static_cast<size_t>(stripe_)]};
  return a;
}

SequencerActions ScanSequencer::resend_goal(double now_s, const std::string& why) {
  if (goal_sends_ >= config_.goal_attempts)
    return fail(fmt::format("stripe {}: {} ({} goals sent for it)", stripe_, why, goal_sends_));
  // A new goal id: a restarted comm does not know the old one and would run
  // a resend of it as a new goal (the arm would log the same goal twice).
  SequencerActions a = send_goal(now_s);
  a.changed = true;
  return a;
}

SequencerActions ScanSequencer::next_stripe(double now_s) {
  ++pos_;
  if (pos_ < order_.size()) {
    stripe_ = order_[pos_];
    goal_sends_ = 0;
    return send_goal(now_s);
  }
  // The end of this round: wait for the points of what was imaged.
  phase_ = Phase::kSettling;
  phase_since_s_ = now_s;
  return settle(now_s);
}

SequencerActions ScanSequencer::settle(double now_s) {
  if (phase_ != Phase::kSettling) return {};
  bool all_ranged = true;
  for (const int i : imaged_) all_ranged = all_ranged && ranged_.count(i) != 0;
  if (!all_ranged && now_s - phase_since_s_ < config_.ranged_timeout_s) return {};
  std::vector<int> missing;
  for (int i = 0; i < planned(); ++i)
    if (ranged_.count(i) == 0) missing.push_back(i);
  SequencerActions a;
  a.changed = true;
  if (!missing.empty() && round_ < config_.retake_rounds) {
    ++round_;
    retaken_ += static_cast<int>(missing.size());
    order_ = std::move(missing);
    pos_ = 0;
    stripe_ = order_.front();
    goal_sends_ = 0;
    a = send_goal(now_s);
    a.changed = true;
    return a;
  }
  state_ = ScanState::kCaptured;
  phase_ = Phase::kCloud;
  phase_since_s_ = now_s;
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
  imaged_.insert(stripe_);
  ++images_;
  if (first_image_s_ < 0) first_image_s_ = now_s;
  last_image_s_ = now_s;
  SequencerActions a = next_stripe(now_s);  // the arm moves on while this image is processed
  a.changed = true;
  return a;
}

SequencerActions ScanSequencer::on_points(int64_t image_index, double now_s) {
  if (phase_ != Phase::kProbeImaged || image_index != probe_image_) return {};
  state_ = ScanState::kRunning;
  if (order_.empty()) {  // nothing to scan
    phase_ = Phase::kSettling;
    phase_since_s_ = now_s;
    return settle(now_s);
  }
  pos_ = 0;
  stripe_ = order_.front();
  goal_sends_ = 0;
  SequencerActions a = send_goal(now_s);
  a.changed = true;
  return a;
}

SequencerActions ScanSequencer::on_ranged(int stripe, int range_holds, double now_s) {
  if (state_ != ScanState::kRunning || stripe < 0 || stripe >= planned()) return {};
  ranged_.insert(stripe);
  if (range_holds < static_cast<int>(ranged_.size())) {
    // The range process holds fewer of this scan's stripes than it has
    // ranged: it restarted and lost them. Which it still holds is not known
    // beyond this one; the rest are taken again.
    ++range_losses_;
    ranged_ = {stripe};
  }
  return settle(now_s);
}

SequencerActions ScanSequencer::on_motion_done(int64_t goal_id, int status,
                                               const std::string& reason, double now_s) {
  if (phase_ != Phase::kMoving || goal_id != goal_id_) return {};
  motion_s_ += now_s - phase_since_s_;
  switch (status) {
    case 0:  // done: the arm is at rest there
      phase_ = Phase::kCapturing;
      return capture(now_s, false);
    case 1: {  // rejected: skip the stripe (a later round asks once more)
      refused_.insert(stripe_);
      SequencerActions a = next_stripe(now_s);
      a.changed = true;
      return a;
    }
    case 2:  // failed (the arm stopped): again, from where it stands
      return resend_goal(now_s, "the arm failed the move: " + reason);
    default:  // timed out in comm (the arm not answering, or restarted): again
      return resend_goal(now_s, "the arm timed out on the move: " + reason);
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
      if (now_s - std::max(phase_since_s_, arm_moving_s_) > config_.motion_timeout_s)
        return resend_goal(now_s, fmt::format("no MOTION_DONE for goal {} in {:.0f} s", goal_id_,
                                              config_.motion_timeout_s));
      return {};
    case Phase::kSettling:
      return settle(now_s);
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

void ScanSequencer::on_arm_moving(double now_s) {
  if (phase_ == Phase::kMoving) arm_moving_s_ = now_s;
}

double ScanSequencer::elapsed_s(double now_s) const {
  if (first_goal_s_ < 0) return 0.0;
  return (done_s_ >= 0 ? done_s_ : now_s) - first_goal_s_;
}

double ScanSequencer::stripes_per_s() const {
  if (images_ < 2 || !(last_image_s_ > first_image_s_)) return 0.0;
  return (images_ - 1) / (last_image_s_ - first_image_s_);
}

}  // namespace ephor::stripe
