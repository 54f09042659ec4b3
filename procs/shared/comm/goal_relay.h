#pragma once
// GoalRelay: the protocol of ephor-comm (seed 003, section 3.3), as a pure
// state machine. The planner hands it goals and never waits; the relay turns
// each goal into an arm command with a sequence number, (re)transmits it until
// the arm answers, waits for the end of the motion, and reports how the goal
// ended. The arm executes each seq at most once and answers a repeated seq by
// repeating its newest ack for it, so retransmitting is always safe and is the
// only recovery for loss in either direction.
//
// Time is passed in by the caller, in microseconds of one monotonic clock
// (ephor-comm uses CLOCK_MONOTONIC); the relay has no clock and no threads, so
// tests simulate time. Not thread-safe: one thread calls everything.
//
// Lifecycle of one goal:
//   submit() -> pending (newest wins: a newer goal replaces a pending one that
//   was never sent; a goal already sent is not aborted, the newer one waits
//   for it to end) -> in flight, phase kDelivering: the command is sent at
//   once and again every retry interval (the same command: the caller stamps
//   every transmission of a seq with the wall time of its first send), until
//   the arm answers or max_attempts sends went unanswered (TIMEOUT) ->
//   phase kExecuting after ACCEPTED: the relay polls (re-sends the same seq)
//   every poll interval so a lost DONE is recovered and the arm hears comm is
//   alive, until DONE / FAILED arrives or the done deadline passes (TIMEOUT).
//   REJECTED, DONE and FAILED end the goal in either phase.
//
// Sequence numbers increase by one per goal sent and start above any seq the
// arm reports (arm state, or an ack for a seq this relay did not send), so a
// restarted comm never reuses a seq the arm has already executed. Until the
// arm's state has been heard, goals are held (option wait_for_arm_state). If
// the arm nevertheless answers the in-flight seq for another goal (it lost
// track, or another comm ran), the goal moves to a fresh seq; after two such
// moves it ends FAILED (the arm's acks do not match its commands).
//
// Duplicates: a goal with the same (goal_id, planned_utime) as the pending,
// the in-flight or a recently finished goal is ignored (a planner may
// republish its current goal), so a republished goal is never executed twice;
// planned_utime keeps a restarted planner's new goal 1 apart from the old one. Superseded goals get
// no motion_done: motion_done_t has no status for them, and the planner only waits for its newest
// goal.

#include <array>
#include <cstdint>
#include <deque>
#include <optional>
#include <string>
#include <vector>

namespace ephor::comm {

// Where the end effector works (arm_goal_t.PLANE_*).
enum class Plane : int8_t { kElevation = 0, kObject = 1 };

// One arm goal from the planner (arm_goal_t without the LCM header).
struct Goal {
  int64_t goal_id = 0;        // planner's id, unique per planner run
  int64_t planned_utime = 0;  // arm_goal_t.utime: wall clock when planned, us (identity, see above)
  int8_t kind = 0;         // arm_goal_t.KIND_* (0 image, 1 pose, 2 joints, 3 trajectory); validated
  int8_t plane = 0;        // kind image: Plane as sent; validated by goal_problem()
  float u = 0.0f;          // kind image: target in the image, px
  float v = 0.0f;          // px
  float theta_rad = 0.0f;  // manipulator orientation in the image, rad
  float max_speed_mm_s = 0.0f;          // end-effector speed cap, mm/s; 0 = the arm's default
  int64_t source_frame_utime = 0;       // capture time of the frame behind the goal, us (passed on)
  int32_t target_object = -1;           // object id served, -1 = none
  std::array<double, 3> position_mm{};  // kind pose: tool tip in the work cell frame, mm
  std::array<double, 6> joints_rad{};   // kind joints: rad
  // Kind trajectory (3): samples at t_s (s from the start), positions (rad)
  // and velocities (rad/s); the arm checks them against its limits.
  std::vector<float> traj_t_s;
  std::vector<std::array<double, 6>> traj_q_rad, traj_qd_rad_s;
};

// One transmission of an arm command (arm_cmd_t without header and utime).
// The caller stamps arm_cmd_t.utime with the wall time of the seq's first
// send and repeats it unchanged in every retransmission and poll: the arm
// identifies a command by (seq, utime) and refuses one it has not seen before
// that is older than its max age.
struct Command {
  int64_t seq = 0;
  Goal goal;
  int32_t transmission = 0;  // 1 = first send of this seq, 2.. = retransmission or poll
};

enum class AckStatus : int8_t { kAccepted = 0, kDone = 1, kRejected = 2, kFailed = 3 };

// The arm's answer (arm_ack_t). Only acks from the configured arm reach here.
struct Ack {
  int64_t seq = 0;
  int64_t goal_id = 0;
  AckStatus status = AckStatus::kAccepted;
  std::string reason;
  float planned_duration_s = 0.0f;  // planned motion time, s (with ACCEPTED)
};

// The part of arm_state_t the relay needs.
struct ArmProgress {
  int64_t executing_seq = 0;  // 0 = none
  int64_t last_done_seq = 0;
};

enum class Outcome : int8_t {
  kDone = 0,
  kRejected = 1,
  kFailed = 2,
  kTimeout = 3
};  // motion_done_t

const char* to_string(Outcome outcome);
const char* to_string(AckStatus status);

// How a goal ended (motion_done_t).
struct MotionDone {
  int64_t goal_id = 0;
  int64_t seq = 0;  // 0 when the goal never got a seq (invalid, or no arm heard)
  Outcome status = Outcome::kDone;
  std::string reason;
  // Transmissions until the arm first answered (or all of them when it never
  // did): how many tries delivery took. Polls after ACCEPTED are not included
  // (see RelayCounters::polls).
  int32_t attempts = 0;
  int64_t round_trip_us = 0;  // first send to the end, us (0 when never sent)
};

// A final ack (DONE / FAILED / REJECTED) for a seq already reported TIMEOUT:
// the planner was told the wrong story, so the caller logs it.
struct LateConfirmation {
  int64_t goal_id = 0;
  int64_t seq = 0;
  AckStatus status = AckStatus::kDone;
  std::string reason;
  int64_t after_timeout_us = 0;  // how long after the TIMEOUT it arrived, us
};

// What the caller must publish / log after step().
struct RelayOutput {
  std::vector<Command> commands;
  std::vector<MotionDone> done;
  std::vector<LateConfirmation> late;
};

struct RelayCounters {
  int64_t goals_received = 0;    // every submit()
  int64_t goals_invalid = 0;     // refused by goal_problem(), reported REJECTED, never sent
  int64_t goals_superseded = 0;  // replaced while pending, never sent, not reported
  int64_t goals_duplicate = 0;   // same goal as the pending, in-flight or a recently finished one
  int64_t commands_sent = 0;     // first transmissions (one per seq)
  int64_t retransmissions = 0;   // re-sends before the arm answered
  int64_t polls = 0;             // re-sends after ACCEPTED (status query / keep-alive)
  int64_t acks_unknown = 0;      // acks for a seq (or goal) not in flight and not recently finished
  int64_t acks_duplicate = 0;    // repeated answers for the in-flight or a finished seq (harmless)
  int64_t late_confirmations = 0;  // final acks after TIMEOUT was reported
  int64_t seq_conflicts = 0;       // in-flight seq answered for another goal: moved to a fresh seq
  int64_t implausible_seqs = 0;    // negative or beyond kMaxSeq in arm state or an ack: ignored
  int64_t done = 0;
  int64_t rejected = 0;  // by the arm, plus goals_invalid
  int64_t failed = 0;
  int64_t timeouts = 0;
};

struct RelayOptions {
  int64_t retry_interval_us = 100'000;  // re-send until the arm answers, us
  int32_t max_attempts = 10;            // sends without an answer before TIMEOUT
  int64_t poll_interval_us = 200'000;   // re-send while the motion runs, us
  // The done deadline after ACCEPTED: planned duration * (1 + factor) + margin.
  double done_margin_factor = 0.5;
  int64_t done_margin_us = 1'000'000;
  float max_planned_duration_s = 600.0f;  // larger or non-finite planned durations are clamped
  // Hold goals until the arm's seq is known (arm state or an ack), so a
  // restarted comm cannot reuse a seq. A goal held longer than
  // max_attempts * retry_interval ends TIMEOUT ("no arm heard").
  bool wait_for_arm_state = true;
  int32_t finished_memory = 64;  // finished goals remembered (late/duplicate acks, duplicate goals)
  // Newest goal wins also over a motion in progress: a pending goal is sent
  // at once when the in-flight one has been ACCEPTED (the arm replaces the
  // motion; the old goal ends FAILED "superseded"). For planners that refine
  // one target continuously (catching); shepherding waits for each motion.
  // Never while the in-flight seq is still being delivered: a late copy of
  // it must not reach the arm after the newer command.
  bool preempt_in_flight = false;
};

// Why a goal cannot be sent (non-finite or out-of-range field), or nullopt.
std::optional<std::string> goal_problem(const Goal& goal);

class GoalRelay {
 public:
  // Seqs the relay follows from the arm; beyond it a message is corrupt.
  static constexpr int64_t kMaxSeq = int64_t{1} << 62;

  // Throws std::invalid_argument naming the bad option.
  explicit GoalRelay(RelayOptions options = {});

  // A goal from the planner. Invalid goals end at once as REJECTED (reported
  // by the next step()) and do not disturb the pending or in-flight goal.
  void submit(const Goal& goal, int64_t now_us);
  // An answer from the arm. Acks for other seqs are counted and ignored.
  void on_ack(const Ack& ack, int64_t now_us);
  // The arm's state: lifts the start-up hold and raises the next seq.
  void on_arm_progress(const ArmProgress& progress, int64_t now_us);

  // Advances timers to `now_us`, starts the pending goal when nothing is in
  // flight, and returns what to send and report since the last step().
  RelayOutput step(int64_t now_us);

  // The seq the next goal will get.
  int64_t next_seq() const { return next_seq_; }
  bool busy() const { return in_flight_.has_value() || pending_.has_value(); }
  bool arm_heard() const { return arm_heard_; }
  const RelayCounters& counters() const { return counters_; }
  const RelayOptions& options() const { return options_; }

 private:
  enum class Phase { kDelivering, kExecuting };
  struct Pending {
    Goal goal;
    int64_t received_us = 0;
  };
  struct InFlight {
    int64_t seq = 0;
    Goal goal;
    Phase phase = Phase::kDelivering;
    int32_t attempts = 0;       // transmissions before the first answer
    int32_t transmissions = 0;  // all transmissions incl. polls
    int32_t seq_moves = 0;      // fresh seqs taken after goal_id mismatches
    int64_t first_sent_us = 0;
    int64_t last_sent_us = 0;
    int64_t done_deadline_us = 0;  // kExecuting only
  };
  struct Finished {
    int64_t seq = 0;
    int64_t goal_id = 0;
    int64_t planned_utime = 0;
    Outcome status = Outcome::kDone;
    int64_t finished_us = 0;
    bool late_reported = false;
  };

  void transmit(RelayOutput& out, int64_t now_us, bool first);
  void finish(Outcome status, std::string reason, int64_t now_us);
  void raise_next_seq(int64_t seen_seq);
  void on_finished_seq_ack(Finished& f, const Ack& ack, int64_t now_us);
  bool is_duplicate(const Goal& goal) const;
  void remember_finished(Finished f);

  RelayOptions options_;
  RelayCounters counters_;
  int64_t next_seq_ = 1;
  bool arm_heard_ = false;
  std::optional<Pending> pending_;
  std::optional<InFlight> in_flight_;
  std::deque<Finished> finished_;  // newest at the back
  // Reports produced between steps (submit / on_ack), handed out by step().
  std::vector<MotionDone> done_out_;
  std::vector<LateConfirmation> late_out_;
};

}  // namespace ephor::comm
