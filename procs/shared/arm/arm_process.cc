#include "procs/shared/arm/arm_process.h"

#include <cmath>
#include <utility>

#include <spdlog/spdlog.h>

#include "common/arm/arm_workcell.h"
#include "common/time/clock.h"
#include "ephor/arm_goal_t.hpp"
#include "procs/shared/arm/arm_cmd_message.h"
#include "procs/shared/arm/controlled_stop.h"

namespace ephor::arm {

static_assert(kPlaneElevation == arm_goal_t::PLANE_ELEVATION);
static_assert(kPlaneObject == arm_goal_t::PLANE_OBJECT);
static_assert(kKindImage == arm_goal_t::KIND_IMAGE);
static_assert(kKindPose == arm_goal_t::KIND_POSE);
static_assert(kKindJoints == arm_goal_t::KIND_JOINTS);
static_assert(kKindTrajectory == arm_goal_t::KIND_TRAJECTORY);
static_assert(static_cast<int>(AckStatus::kAccepted) == arm_ack_t::STATUS_ACCEPTED);
static_assert(static_cast<int>(AckStatus::kDone) == arm_ack_t::STATUS_DONE);
static_assert(static_cast<int>(AckStatus::kRejected) == arm_ack_t::STATUS_REJECTED);
static_assert(static_cast<int>(AckStatus::kFailed) == arm_ack_t::STATUS_FAILED);

ArmClock ArmClock::system() {
  return {[] { return ephor::mono_us(); }, [] { return ephor::wall_us(); }};
}

ArmProcess::ArmProcess(ArmOutputs& outputs, const geometry::Workcell& cell,
                       calibration::FieldCalibration calibration,
                       const geometry::OverheadCamera& camera, ArmProcessOptions options,
                       ArmClock clock)
    : outputs_(outputs),
      clock_(std::move(clock)),
      cell_(cell),
      options_(options),
      arm_(make_puma(cell)),
      validator_(calibration, cell, {camera.width_px, camera.height_px, options.max_speed_mm_s}),
      calibration_(std::move(calibration)),
      planner_(cell, planner_config(cell, options)),
      ledger_(clock_.wall_us()),
      gate_({static_cast<int64_t>(options.comm_timeout_ms * 1e3)}),
      next_trajectory_seq_(clock_.wall_us()) {}

MotionPlannerConfig ArmProcess::planner_config(const geometry::Workcell& cell,
                                               const ArmProcessOptions& o) {
  MotionPlannerConfig c;
  c.max_speed_mm_s = o.max_speed_mm_s;
  c.cartesian_accel_mm_s2 = cell.tool_accel_mm_s2;
  c.joint_planner.time_budget_s = o.planner_time_budget_s;
  return c;
}

// Bus thread.
void ArmProcess::on_command(const arm_cmd_t& m) {
  if (m.header.sender != options_.accept_from) {
    const int64_t n = ++foreign_;
    if (n <= 5 || n % 100 == 0)
      spdlog::warn("ARM_CMD seq {} from '{}' ignored: only '{}' may command the arm ({} so far)",
                   m.seq, m.header.sender, options_.accept_from, n);
    return;
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    gate_.on_comm_heard(clock_.mono_us());
  }
  {
    std::lock_guard<std::mutex> lock(queue_mutex_);
    if (queue_.size() >= 64) {
      spdlog::warn("ARM_CMD queue full: dropping seq {} (the sender will retransmit)",
                   queue_.front().seq);
      queue_.pop_front();
    }
    queue_.push_back(m);
  }
  outputs_.command_queued();
}

// Bus thread: acted on at once, not queued behind commands being planned.
void ArmProcess::on_estop(const estop_t& m) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!gate_.on_estop(m.stop, m.header.sender, m.reason)) return;  // a repeat
  if (!m.stop) {
    spdlog::warn("emergency stop released by '{}' ({}): commands accepted again", m.header.sender,
                 m.reason);
    return;
  }
  spdlog::error("EMERGENCY STOP from '{}': {}", m.header.sender, m.reason);
  stop_motion(*gate_.stop_reason(true, clock_.mono_us()));
}

// Bus thread.
void ArmProcess::on_servo(const joint_state_t& m) {
  ServoState s;
  s.utime = m.utime;
  for (int i = 0; i < 6; ++i) {
    s.q[i] = m.q[i];
    s.qd[i] = m.qd[i];
  }
  if (!s.q.allFinite() || !s.qd.allFinite()) {
    const int64_t n = ++bad_servo_;
    if (n <= 5 || n % 100 == 0)
      spdlog::warn("ARM_SERVO with non-finite joints ignored ({} so far)", n);
    return;
  }
  s.trajectory_seq = m.trajectory_seq;
  s.trajectory_done = m.trajectory_done;
  s.fault = m.fault;
  s.fault_reason = m.fault_reason;
  std::lock_guard<std::mutex> lock(mutex_);
  servo_ = s;
  servo_mono_us_ = clock_.mono_us();
  finish_if(monitor_.on_servo(s, clock_.mono_us()));
  deliver();
}

// Task "command": validates, plans and sends every queued command in order.
void ArmProcess::command_job() {
  for (;;) {
    arm_cmd_t m;
    {
      std::lock_guard<std::mutex> lock(queue_mutex_);
      if (queue_.empty()) return;
      m = queue_.front();
      queue_.pop_front();
    }
    handle_command(m);
  }
}

// Task "state", every 10 ms.
void ArmProcess::state_job() {
  std::lock_guard<std::mutex> lock(mutex_);
  finish_if(monitor_.on_tick(clock_.mono_us()));
  deliver();
  if (const auto why = gate_.stop_reason(monitor_.busy(), clock_.mono_us())) {
    spdlog::error("{}", *why);
    stop_motion(*why);
  }
  if (!servo_) return;  // nothing known about the arm yet
  const ToolInField tool = tool_in_field(cell_, servo_->q);
  const auto plane = nearest_plane(tool.tip_mm.z());
  const Eigen::Vector2d uv = calibration_.field_to_image(tool.tip_mm.x(), tool.tip_mm.y(), plane);
  const Eigen::Vector2d uv2 =
      calibration_.field_to_image(tool.tip_mm.x() + std::cos(tool.theta_rad),
                                  tool.tip_mm.y() + std::sin(tool.theta_rad), plane);
  constexpr double kDt = 1e-3;  // s, for the tool speed J qd by a finite difference
  const double speed = (arm_.forward(servo_->q + kDt * servo_->qd).translation() -
                        arm_.forward(servo_->q).translation())
                           .norm() /
                       kDt;
  arm_state_t s;
  s.utime = servo_->utime;
  for (int i = 0; i < 6; ++i) {
    s.q[i] = servo_->q[i];
    s.qd[i] = servo_->qd[i];
  }
  s.x_mm = static_cast<float>(tool.tip_mm.x());
  s.y_mm = static_cast<float>(tool.tip_mm.y());
  s.z_mm = static_cast<float>(tool.tip_mm.z());
  s.u = static_cast<float>(uv.x());
  s.v = static_cast<float>(uv.y());
  s.theta_rad = static_cast<float>(std::atan2(uv2.y() - uv.y(), uv2.x() - uv.x()));
  s.moving = monitor_.busy() || servo_->qd.cwiseAbs().maxCoeff() > 1e-3;
  if (s.moving) {
    s.plane = -1;
  } else if (monitor_.last_done_plane() >= 0) {
    s.plane = static_cast<int8_t>(monitor_.last_done_plane());
  } else {
    s.plane = static_cast<int8_t>(plane_by_height(tool.tip_mm.z()));
  }
  s.executing_seq = monitor_.executing_seq();
  s.last_done_seq = monitor_.last_done_seq();
  s.speed_mm_s = static_cast<float>(speed);
  outputs_.publish_state(s);
}

void ArmProcess::log_summary() const {
  spdlog::info(
      "commands: {} accepted, {} rejected, {} sent before this arm started (failed, not "
      "executed), {} repeats answered, {} foreign ignored; trajectories sent again: {}",
      accepted_.load(), rejected_.load(), from_before_start_.load(), repeats_.load(),
      foreign_.load(), resends_.load());
}

calibration::Plane ArmProcess::nearest_plane(double z_mm) const {
  return std::abs(z_mm - cell_.object_plane_z_mm) < std::abs(z_mm - cell_.elevation_plane_z_mm)
             ? calibration::Plane::kObject
             : calibration::Plane::kElevation;
}
int ArmProcess::plane_by_height(double z_mm) const {
  if (std::abs(z_mm - cell_.object_plane_z_mm) < 5.0) return kPlaneObject;
  if (std::abs(z_mm - cell_.elevation_plane_z_mm) < 5.0) return kPlaneElevation;
  return -1;
}

// Caller holds mutex_.
void ArmProcess::publish_ack(const ArmAck& ack, int64_t cmd_utime) {
  ledger_.record(ack.seq, cmd_utime, ack);
  arm_ack_t m;
  m.utime = clock_.wall_us();
  m.seq = ack.seq;
  m.goal_id = ack.goal_id;
  m.status = static_cast<int8_t>(ack.status);
  m.reason = ack.reason;
  m.planned_duration_s = static_cast<float>(ack.planned_duration_s);
  outputs_.publish_ack(m);
  if (ack.status == AckStatus::kRejected || ack.status == AckStatus::kFailed) {
    spdlog::warn("seq {} {}: {}", ack.seq, to_string(ack.status), ack.reason);
  } else {
    spdlog::debug("seq {} {}", ack.seq, to_string(ack.status));
  }
}
// Caller holds mutex_.
void ArmProcess::finish_if(const std::optional<ArmAck>& ack) {
  if (ack) publish_ack(*ack, executing_cmd_utime_);
}
// Caller holds mutex_.
void ArmProcess::reject(const arm_cmd_t& m, std::string reason) {
  ArmAck ack;
  ack.seq = m.seq;
  ack.goal_id = m.goal_id;
  ack.status = AckStatus::kRejected;
  ack.reason = std::move(reason);
  ++rejected_;
  publish_ack(ack, m.utime);
}

// Caller holds mutex_. FAILED, not REJECTED: the command may have been
// executed (by the arm's run before a restart), which REJECTED would deny.
void ArmProcess::fail_unknown(const arm_cmd_t& m, std::string reason) {
  ArmAck ack;
  ack.seq = m.seq;
  ack.goal_id = m.goal_id;
  ack.status = AckStatus::kFailed;
  ack.reason = std::move(reason);
  ++from_before_start_;
  publish_ack(ack, m.utime);
}

void ArmProcess::handle_command(const arm_cmd_t& m) {
  Joints start;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (const auto previous = ledger_.find(m.seq, m.utime)) {
      ++repeats_;
      publish_ack(*previous, m.utime);  // at most once: answer again, do not move again
      return;
    }
    if (const auto why = gate_.refuse_command()) return reject(m, *why);
    if (m.utime <= 0) return reject(m, "command has no send time (utime <= 0)");
    // Only now: a utime of INT64_MIN overflowed the age (fuzz target arm_process).
    const int64_t age_us = clock_.wall_us() - m.utime;
    const auto max_age_us = static_cast<int64_t>(options_.max_age_ms * 1000.0);
    // Too old or from the future: refused whenever it was first sent (the
    // restart rule below never needs to vouch for it).
    if (age_us > max_age_us)
      return reject(m, fmt::format("stale: sent {:.0f} ms ago (max age {:.0f} ms)", age_us / 1e3,
                                   options_.max_age_ms));
    if (age_us < -max_age_us)
      return reject(
          m, fmt::format("send time {:.0f} ms in the future: clocks out of sync?", -age_us / 1e3));
    // Sent before this run began: a restarted arm cannot know whether the
    // run before executed it (CommandLedger), so it never does.
    if (auto why = ledger_.refusal(m.seq, m.utime)) return fail_unknown(m, std::move(*why));
    if (!servo_) return reject(m, "no joint state from the servo yet (ARM_SERVO)");
    const double silent_ms = (clock_.mono_us() - servo_mono_us_) / 1e3;
    if (silent_ms > options_.servo_silence_ms)
      return reject(m, fmt::format("servo silent for {:.0f} ms (ARM_SERVO)", silent_ms));
    start = servo_->q;
  }

  const ArmCommand cmd = command_from_message(m);

  // Validate and plan without the lock (OMPL may take its time budget); if
  // the arm moved meanwhile, plan again from where it is now.
  Validation v;
  MotionPlan plan;
  for (int attempt = 0; attempt < 3; ++attempt) {
    v = validator_.validate(cmd, start);
    if (v.ok && cmd.kind == kKindTrajectory) {
      // Executed as given: the validator checked it against the limits.
      plan = MotionPlan{};
      plan.ok = true;
      plan.kind = MotionKind::kJointSpace;
      plan.goal_q = v.target.goal_q;
      plan.trajectory = cmd.trajectory;
    } else if (v.ok) {
      plan = planner_.plan(start, v.target.pose_in_base, v.target.speed_mm_s);
    }
    std::lock_guard<std::mutex> lock(mutex_);
    if (!v.ok) return reject(m, v.reason);
    if (!plan.ok) return reject(m, plan.reason);
    if (const auto why = gate_.refuse_command()) return reject(m, *why);  // while planning
    if ((servo_->q - start).cwiseAbs().maxCoeff() <= options_.replan_tolerance_rad) {
      send(m, v, plan);
      return;
    }
    start = servo_->q;
  }
  std::lock_guard<std::mutex> lock(mutex_);
  reject(m, "the arm kept moving while the motion was planned (3 attempts)");
}

// Brings the arm to rest now and fails the motion in progress. Caller
// holds mutex_.
void ArmProcess::stop_motion(const std::string& why) {
  finish_if(monitor_.abort(why));
  if (!servo_) return;  // never heard the servo: nothing was sent to it
  publish_trajectory(controlled_stop(servo_->q, servo_->qd, arm_.limits()),
                     /*stop=*/true);
}

// Sends the last trajectory again when the servo has not taken it up
// (TrajectoryDelivery: a lost datagram). Caller holds mutex_.
void ArmProcess::deliver() {
  if (!servo_) return;
  const int64_t now = clock_.mono_us();
  switch (delivery_.check(*servo_, now)) {
    case TrajectoryDelivery::Action::kNone:
      return;
    case TrajectoryDelivery::Action::kResend: {
      outputs_.publish_trajectory(last_trajectory_, /*stop=*/false);
      delivery_.resent(now);
      const int64_t n = ++resends_;
      if (n <= 10 || n % 100 == 0)
        spdlog::warn("trajectory {} not taken up by the servo (lost?): sent again ({} so far)",
                     last_trajectory_.seq, n);
      return;
    }
    case TrajectoryDelivery::Action::kReplanStop: {
      const int64_t n = ++resends_;
      if (n <= 10 || n % 100 == 0)
        spdlog::warn(
            "stop trajectory {} not taken up by the servo (lost?): stopping again "
            "from where the arm is ({} so far)",
            last_trajectory_.seq, n);
      publish_trajectory(controlled_stop(servo_->q, servo_->qd, arm_.limits()),
                         /*stop=*/true);
      return;
    }
    case TrajectoryDelivery::Action::kGiveUp:
      ++resends_;
      finish_if(monitor_.abort(delivery_.why()));
      return;
  }
}

// Caller holds mutex_. Returns the trajectory's seq. `stop`: a controlled
// stop (sent again from where the arm is if lost), else a motion.
int64_t ArmProcess::publish_trajectory(const Trajectory& trajectory, bool stop) {
  joint_trajectory_t t;
  t.utime = clock_.wall_us();
  t.seq = ++next_trajectory_seq_;
  t.num_points = static_cast<int32_t>(trajectory.points.size());
  for (const auto& p : trajectory.points) {
    t.t_s.push_back(static_cast<float>(p.t_s));
    t.q.emplace_back(p.q.data(), p.q.data() + 6);
    t.qd.emplace_back(p.qd.data(), p.qd.data() + 6);
  }
  outputs_.publish_trajectory(t, stop);
  const Joints first = !trajectory.points.empty() ? trajectory.points.front().q
                       : servo_                   ? servo_->q
                                                  : Joints::Zero();
  delivery_.sent(t.seq, first, stop, clock_.mono_us());
  last_trajectory_ = std::move(t);
  return last_trajectory_.seq;
}

// Caller holds mutex_.
void ArmProcess::send(const arm_cmd_t& m, const Validation& v, const MotionPlan& plan) {
  finish_if(monitor_.preempt(m.seq));
  const int64_t trajectory_seq = publish_trajectory(plan.trajectory, /*stop=*/false);
  monitor_.set_plane(m.plane);
  monitor_.start(m.seq, m.goal_id, trajectory_seq, plan.goal_q, plan.trajectory.duration_s(),
                 clock_.mono_us());
  executing_cmd_utime_ = m.utime;
  ArmAck ack;
  ack.seq = m.seq;
  ack.goal_id = m.goal_id;
  ack.status = AckStatus::kAccepted;
  ack.planned_duration_s = plan.trajectory.duration_s();
  ++accepted_;
  publish_ack(ack, m.utime);
  spdlog::info(
      "seq {} goal {}: {} move to ({:.0f}, {:.0f}, {:.0f}) mm, {:.2f} s, speed scale {:.2f}{}",
      m.seq, m.goal_id, m.kind == kKindTrajectory ? "given trajectory" : to_string(plan.kind),
      v.target.tip_mm.x(), v.target.tip_mm.y(), v.target.tip_mm.z(), plan.trajectory.duration_s(),
      plan.speed_scale,
      plan.cartesian_rejected.empty()
          ? ""
          : " (straight line not possible: " + plan.cartesian_rejected + ")");
}

}  // namespace ephor::arm
