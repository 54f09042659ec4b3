#pragma once
// The scan planner's sequence (paper 004, section 5: "When scanning a
// regular pattern, arm motion can be overlapped with processing the data
// from the previous image"), as a state machine with time passed in and
// the messages to send as its answers (no LCM; main.cc wires it):
//
//  1. Probe: one image at the arm's start pose, outside any scan, must come
//     back through the whole pipeline (camera -> stripe -> range: its
//     STRIPE_POINTS heard) before the arm moves, so no stripe is lost to a
//     process still starting. Re-asked every capture_timeout_s.
//  2. For each stripe: the joint goal (ARM_GOAL, through comm to the arm);
//     on its MOTION_DONE the capture (STRIPE_CAPTURE); on the image
//     (STRIPE_IMAGE, taken at rest with its joint readings) at once the next
//     stripe's goal - the arm moves while the stripe and range processes
//     work on the image just taken. A goal the arm refuses (REJECTED) skips
//     its stripe. A goal that FAILED (the arm stopped: comm went quiet, a
//     servo fault) or timed out in comm, or whose MOTION_DONE never came
//     while the arm stood still (comm or the arm restarted, the goal or its
//     answer lost), is sent again under a new goal id (never the same id
//     twice: a restarted comm would run it again), goal_attempts times in
//     all, then the scan fails. A capture unanswered for capture_timeout_s
//     is asked again (same request id: the camera answers a repeat with the
//     same image).
//  3. Nothing lost (issue 18): a stripe counts as taken once the range
//     process has its points (STRIPE_POINTS of this scan, on_ranged). After
//     the raster's last image the sequencer waits up to ranged_timeout_s for
//     every image's points, then goes back for each stripe without points
//     (its image or profile lost, the stripe or range process restarted, its
//     goal refused) in raster order: up to retake_rounds such rounds. When
//     the range process has restarted (it says it holds fewer stripes of the
//     scan than were ranged), the stripes ranged before are taken again.
//     A restarted planner begins a new scan (see procs/stripe/README.md).
//  4. Captured: every stripe's image taken; the range process completes the
//     cloud (STRIPE_CLOUD, complete) -> done, or failed after cloud_timeout_s.

#include <cstdint>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "common/arm/puma560.h"

namespace ephor::stripe {

struct SequencerConfig {
  double capture_timeout_s = 1.0;  // ask again for an image not heard this long
  int capture_attempts = 10;       // then fail
  double motion_timeout_s = 4.0;   // no MOTION_DONE for a goal this long: send it again
  int goal_attempts = 5;           // sends of one stripe's goal (timeouts) before failing
  double ranged_timeout_s = 2.0;   // after the raster, wait this long for points, then retake
  int retake_rounds = 2;           // rounds of going back for stripes without points
  double cloud_timeout_s = 20.0;   // no complete cloud this long after the last image: fail
};

enum class ScanState { kWaiting, kRunning, kCaptured, kDone, kFailed };
const char* to_string(ScanState s);

struct GoalAction {
  int64_t goal_id = 0;
  int stripe = 0;
  arm::Joints q = arm::Joints::Zero();
};
struct CaptureAction {
  int64_t request_id = 0;
  int stripe = -1;  // -1: the probe
};
struct SequencerActions {
  std::optional<GoalAction> goal;
  std::optional<CaptureAction> capture;
  bool changed = false;  // the state or a count changed: publish STRIPE_SCAN
};

class ScanSequencer {
 public:
  // goal ids and request ids count up from the firsts given (> 0).
  ScanSequencer(std::vector<arm::Joints> goals, int64_t first_goal_id, int64_t first_request_id,
                SequencerConfig config = {});

  // The arm's state has been heard: the probe is asked for.
  SequencerActions start(double now_s);
  SequencerActions on_image(int64_t request_id, int64_t image_index, double now_s);
  // STRIPE_POINTS for an image (the probe's ends the waiting).
  SequencerActions on_points(int64_t image_index, double now_s);
  // STRIPE_POINTS of this scan: `stripe` is ranged, and the range process
  // holds `range_holds` stripes of the scan (stripe_points_t.scan_stripes).
  SequencerActions on_ranged(int stripe, int range_holds, double now_s);
  // status: motion_done_t.STATUS_* (0 done, 1 rejected, 2 failed, 3 timeout).
  SequencerActions on_motion_done(int64_t goal_id, int status, const std::string& reason,
                                  double now_s);
  SequencerActions on_cloud(int64_t points, double now_s);
  // ARM_STATE says the arm is moving: a goal's answer is not overdue.
  void on_arm_moving(double now_s);
  SequencerActions tick(double now_s);

  ScanState state() const { return state_; }
  bool finished() const { return state_ == ScanState::kDone || state_ == ScanState::kFailed; }
  const std::string& reason() const { return reason_; }
  int planned() const { return static_cast<int>(goals_.size()); }
  // Distinct stripes imaged; stripes refused by the arm and never imaged.
  int captured() const { return static_cast<int>(imaged_.size()); }
  int skipped() const;
  // Stripes ranged; stripes taken again; times the range process lost stripes.
  int ranged() const { return static_cast<int>(ranged_.size()); }
  int retaken() const { return retaken_; }
  int range_losses() const { return range_losses_; }
  int64_t cloud_points() const { return cloud_points_; }
  // Since the first goal (s), the arm's moving time (goal sent to its
  // MOTION_DONE, s), and stripes per second from the first image to the
  // last ((captured - 1) / that time; 0 with fewer than 2).
  double elapsed_s(double now_s) const;
  double motion_s() const { return motion_s_; }
  double stripes_per_s() const;
  // The next free ids (for the scan after this one).
  int64_t next_goal_id() const { return next_goal_id_; }
  int64_t next_request_id() const { return next_request_id_; }

 private:
  enum class Phase { kProbe, kProbeImaged, kMoving, kCapturing, kSettling, kCloud, kNone };
  SequencerActions send_goal(double now_s);
  SequencerActions resend_goal(double now_s, const std::string& why);
  SequencerActions next_stripe(double now_s);
  SequencerActions settle(double now_s);
  SequencerActions capture(double now_s, bool repeat);
  SequencerActions fail(const std::string& why);

  std::vector<arm::Joints> goals_;
  SequencerConfig config_;
  ScanState state_ = ScanState::kWaiting;
  Phase phase_ = Phase::kNone;
  std::string reason_;
  int stripe_ = 0;          // the stripe being moved to / captured
  std::vector<int> order_;  // this round's stripes, in raster order
  size_t pos_ = 0;          // stripe_ == order_[pos_]
  int round_ = 0, goal_sends_ = 0;
  std::set<int> imaged_, ranged_, refused_;
  int images_ = 0, retaken_ = 0, range_losses_ = 0;
  int64_t goal_id_ = 0, request_id_ = 0, probe_image_ = -1;
  int64_t next_goal_id_, next_request_id_;
  double phase_since_s_ = 0.0, request_sent_s_ = 0.0, arm_moving_s_ = -1.0;
  int attempts_ = 0;
  int64_t cloud_points_ = 0;
  double first_goal_s_ = -1.0, first_image_s_ = -1.0, last_image_s_ = -1.0;
  double motion_s_ = 0.0, done_s_ = -1.0;
};

}  // namespace ephor::stripe
