#include "procs/shared/arm/execution_monitor.h"

#include <spdlog/fmt/fmt.h>

#include <limits>

namespace ephor::arm {

void ExecutionMonitor::start(int64_t cmd_seq, int64_t goal_id, int64_t trajectory_seq,
                             const Joints& goal_q, double planned_duration_s, int64_t now_us) {
  busy_ = true;
  cmd_seq_ = cmd_seq;
  goal_id_ = goal_id;
  trajectory_seq_ = trajectory_seq;
  goal_q_ = goal_q;
  planned_duration_s_ = planned_duration_s;
  started_us_ = now_us;
  // In double, saturated: a given trajectory may last up to 3.4e38 s (float
  // times on the wire), whose timeout overflowed int64_t (fuzz target
  // arm_process); such a deadline never comes.
  const double timeout_us =
      (planned_duration_s * config_.timeout_factor + config_.timeout_slack_s) * 1e6;
  constexpr double kNever = 9.0e18;  // us, below INT64_MAX (9.22e18)
  deadline_us_ = timeout_us < kNever - static_cast<double>(now_us)
                     ? now_us + static_cast<int64_t>(timeout_us)
                     : std::numeric_limits<int64_t>::max();
}

ArmAck ExecutionMonitor::finish(AckStatus status, std::string reason) {
  ArmAck ack;
  ack.seq = cmd_seq_;
  ack.goal_id = goal_id_;
  ack.status = status;
  ack.reason = std::move(reason);
  ack.planned_duration_s = planned_duration_s_;
  busy_ = false;
  if (status == AckStatus::kDone) {
    last_done_seq_ = cmd_seq_;
    last_done_plane_ = plane_;
  }
  return ack;
}

std::optional<ArmAck> ExecutionMonitor::on_servo(const ServoState& servo, int64_t now_us) {
  if (!busy_) return std::nullopt;
  const bool ours = servo.trajectory_seq == trajectory_seq_;
  if (servo.fault &&
      (ours || now_us - started_us_ > static_cast<int64_t>(config_.foreign_fault_grace_s * 1e6))) {
    return finish(AckStatus::kFailed,
                  "servo fault: " + (servo.fault_reason.empty() ? std::string("(no reason given)")
                                                                : servo.fault_reason));
  }
  if (ours && servo.trajectory_done && !servo.fault) {
    const Joints err = (servo.q - goal_q_).cwiseAbs();
    int worst = 0;
    const double max_err = err.maxCoeff(&worst);
    if (max_err <= config_.at_target_tolerance_rad) return finish(AckStatus::kDone, "");
    return finish(
        AckStatus::kFailed,
        fmt::format("servo finished trajectory {} but joint {} is {:.3f} rad from the "
                    "target (tolerance {:.3f})",
                    trajectory_seq_, worst + 1, max_err, config_.at_target_tolerance_rad));
  }
  return on_tick(now_us);
}

std::optional<ArmAck> ExecutionMonitor::on_tick(int64_t now_us) {
  if (!busy_ || now_us <= deadline_us_) return std::nullopt;
  return finish(
      AckStatus::kFailed,
      fmt::format("timed out: the servo did not report trajectory {} done within {:.1f} s "
                  "(planned {:.2f} s)",
                  trajectory_seq_,
                  planned_duration_s_ * config_.timeout_factor + config_.timeout_slack_s,
                  planned_duration_s_));
}

std::optional<ArmAck> ExecutionMonitor::preempt(int64_t by_seq) {
  if (!busy_) return std::nullopt;
  return finish(AckStatus::kFailed, fmt::format("replaced by command seq {}", by_seq));
}

std::optional<ArmAck> ExecutionMonitor::abort(std::string reason) {
  if (!busy_) return std::nullopt;
  return finish(AckStatus::kFailed, std::move(reason));
}

}  // namespace ephor::arm
