#pragma once
// ExecutionMonitor: follows the one motion the arm is executing and decides
// when it is DONE (the servo reports the trajectory finished and the joints
// are at the target), or FAILED (servo fault, finished away from the target,
// no completion in time, or replaced by a newer command).
//
// Pure logic fed with servo states and the clock; not thread safe (one owner).

#include <cstdint>
#include <optional>
#include <string>

#include "common/arm/puma560.h"
#include "procs/shared/arm/arm_command.h"

namespace ephor::arm {

struct ExecutionConfig {
  double at_target_tolerance_rad = 0.01;  // every joint within this of the goal for DONE
  // Timeout = planned duration * factor + slack.
  double timeout_factor = 1.5;
  double timeout_slack_s = 2.0;
  // A fault reported for another trajectory (the servo's latched fault of an
  // earlier motion, before it has taken the new trajectory) ends the motion
  // only after this grace period, s.
  double foreign_fault_grace_s = 0.3;
};

class ExecutionMonitor {
 public:
  explicit ExecutionMonitor(ExecutionConfig config = {}) : config_(config) {}

  // A motion was sent to the servo at now_us (wall clock, us).
  void start(int64_t cmd_seq, int64_t goal_id, int64_t trajectory_seq, const Joints& goal_q,
             double planned_duration_s, int64_t now_us);

  // Feeds a servo state; returns the final ack when the motion ends.
  std::optional<ArmAck> on_servo(const ServoState& servo, int64_t now_us);
  // Checks the timeout without a servo state (e.g. the servo went silent).
  std::optional<ArmAck> on_tick(int64_t now_us);
  // A newer command replaces the executing one: its FAILED ack.
  std::optional<ArmAck> preempt(int64_t by_seq);
  // The arm stopped the executing motion itself (emergency stop, comm
  // silent): its FAILED ack with the reason.
  std::optional<ArmAck> abort(std::string reason);

  bool busy() const { return busy_; }
  int64_t executing_seq() const { return busy_ ? cmd_seq_ : 0; }
  int64_t trajectory_seq() const { return trajectory_seq_; }
  int64_t last_done_seq() const { return last_done_seq_; }
  // Plane of the last motion that ended DONE (kPlaneElevation/kPlaneObject), -1 if none.
  int last_done_plane() const { return last_done_plane_; }
  void set_plane(int plane) { plane_ = plane; }

 private:
  ArmAck finish(AckStatus status, std::string reason);

  ExecutionConfig config_;
  bool busy_ = false;
  int64_t cmd_seq_ = 0;
  int64_t goal_id_ = 0;
  int64_t trajectory_seq_ = 0;
  Joints goal_q_ = Joints::Zero();
  double planned_duration_s_ = 0.0;
  int64_t deadline_us_ = 0;
  int64_t started_us_ = 0;
  int64_t last_done_seq_ = 0;
  int plane_ = -1;
  int last_done_plane_ = -1;
};

}  // namespace ephor::arm
