// ephor-arm: the arm server of every system with an arm (first written for
// paper 003, sections 3.6 and 5), on the arm host. It takes arm commands from
// ephor-comm (an image target with plane and orientation, converted to the
// field frame with the calibration; a tool-down pose in the work cell; joint
// angles; or a joint trajectory, checked against the limits and executed as
// given: arm_goal_t.KIND_*), given its work cell and tool by
// --workcell FILE, solves the PUMA 560's inverse kinematics, plans a motion whose
// joint speeds are all within their limits, sends the joint trajectory to the
// servo layer and acknowledges: ACCEPTED, then DONE or FAILED; REJECTED (with
// the reason, never moving) for anything invalid, stale or unreachable.
//
//   subscribes  ARM_CMD (arm_cmd_t, from --accept-from only), ARM_SERVO (joint_state_t),
//               ESTOP (estop_t, from anyone)
//   publishes   ARM_TRAJECTORY (joint_trajectory_t), ARM_ACK (arm_ack_t),
//               ARM_STATE (arm_state_t, task "state" every 10 ms)
//   tasks       state (periodic 10 ms), command (triggered by ARM_CMD: validate, plan, send)
//
// Each command (seq, first-sent utime) is executed at most once: a repeat gets
// the newest ack it was given again, and a command first sent before this
// run of the arm started (a restart) is answered FAILED, never executed: the
// run before may have executed it (CommandLedger). A newer valid command replaces a motion
// in progress (the old one is acknowledged FAILED "replaced by command seq N").
//
// Safety (SafetyGate): an ESTOP stops the arm at once (controlled_stop, sent
// from the bus thread as the message arrives) and latches until released;
// a motion during which comm has gone silent for --comm-timeout-ms is
// stopped by the state task (checked every 10 ms). Both fail the motion.

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <deque>
#include <iostream>
#include <mutex>
#include <optional>
#include <string>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include "common/arm/arm_workcell.h"
#include "common/calibration/field_calibration.h"
#include "common/config/repo_paths.h"
#include "common/config/text_proto.h"
#include "common/geometry/overhead_camera.h"
#include "common/geometry/workcell.h"
#include "common/geometry/workcell_file.h"
#include "common/lcm/bus.h"
#include "common/lcm/channels.h"
#include "common/log/log.h"
#include "common/motion/motion_planner.h"
#include "common/runtime/process_args.h"
#include "common/runtime/task_runtime.h"
#include "common/time/clock.h"
#include "ephor/arm_ack_t.hpp"
#include "ephor/arm_cmd_t.hpp"
#include "ephor/arm_goal_t.hpp"
#include "ephor/arm_state_t.hpp"
#include "ephor/estop_t.hpp"
#include "ephor/joint_state_t.hpp"
#include "ephor/joint_trajectory_t.hpp"
#include "procs/shared/arm/arm_cmd_message.h"
#include "procs/shared/arm/arm_command.h"
#include "procs/shared/arm/command_ledger.h"
#include "procs/shared/arm/command_validator.h"
#include "procs/shared/arm/controlled_stop.h"
#include "procs/shared/arm/execution_monitor.h"
#include "procs/shared/arm/safety_gate.h"
#include "procs/shared/arm/trajectory_delivery.h"

namespace {

using ephor::arm::AckStatus;
using ephor::arm::ArmAck;
using ephor::arm::Joints;

static_assert(ephor::arm::kPlaneElevation == ephor::arm_goal_t::PLANE_ELEVATION);
static_assert(ephor::arm::kPlaneObject == ephor::arm_goal_t::PLANE_OBJECT);
static_assert(ephor::arm::kKindImage == ephor::arm_goal_t::KIND_IMAGE);
static_assert(ephor::arm::kKindPose == ephor::arm_goal_t::KIND_POSE);
static_assert(ephor::arm::kKindJoints == ephor::arm_goal_t::KIND_JOINTS);
static_assert(ephor::arm::kKindTrajectory == ephor::arm_goal_t::KIND_TRAJECTORY);
static_assert(static_cast<int>(AckStatus::kAccepted) == ephor::arm_ack_t::STATUS_ACCEPTED);
static_assert(static_cast<int>(AckStatus::kDone) == ephor::arm_ack_t::STATUS_DONE);
static_assert(static_cast<int>(AckStatus::kRejected) == ephor::arm_ack_t::STATUS_REJECTED);
static_assert(static_cast<int>(AckStatus::kFailed) == ephor::arm_ack_t::STATUS_FAILED);

struct Options {
  double max_speed_mm_s = 300.0;
  double max_age_ms = 500.0;
  std::string accept_from = "comm";
  double servo_silence_ms = 250.0;  // refuse commands when the servo has been quiet this long
  double replan_tolerance_rad = 0.02;
  double comm_timeout_ms = 1000.0;  // stop a motion when comm is silent this long; 0 = never
};

class ArmProcess {
 public:
  ArmProcess(ephor::Bus& bus, ephor::TaskRuntime& runtime, const ephor::geometry::Workcell& cell,
             ephor::calibration::FieldCalibration calibration,
             const ephor::geometry::OverheadCamera& camera, Options options)
      : bus_(bus),
        runtime_(runtime),
        cell_(cell),
        options_(options),
        arm_(ephor::arm::make_puma(cell)),
        validator_(calibration, cell, {camera.width_px, camera.height_px, options.max_speed_mm_s}),
        calibration_(std::move(calibration)),
        planner_(cell, planner_config(cell, options)),
        ledger_(ephor::wall_us()),
        gate_({static_cast<int64_t>(options.comm_timeout_ms * 1e3)}),
        next_trajectory_seq_(ephor::wall_us()) {}

  static ephor::arm::MotionPlannerConfig planner_config(const ephor::geometry::Workcell& cell,
                                                        const Options& o) {
    ephor::arm::MotionPlannerConfig c;
    c.max_speed_mm_s = o.max_speed_mm_s;
    c.cartesian_accel_mm_s2 = cell.tool_accel_mm_s2;
    return c;
  }

  // Bus thread.
  void on_command(const ephor::arm_cmd_t& m) {
    if (m.header.sender != options_.accept_from) {
      const int64_t n = ++foreign_;
      if (n <= 5 || n % 100 == 0)
        spdlog::warn("ARM_CMD seq {} from '{}' ignored: only '{}' may command the arm ({} so far)",
                     m.seq, m.header.sender, options_.accept_from, n);
      return;
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      gate_.on_comm_heard(ephor::mono_us());
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
    runtime_.trigger("command");
  }

  // Bus thread: acted on at once, not queued behind commands being planned.
  void on_estop(const ephor::estop_t& m) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!gate_.on_estop(m.stop, m.header.sender, m.reason)) return;  // a repeat
    if (!m.stop) {
      spdlog::warn("emergency stop released by '{}' ({}): commands accepted again", m.header.sender,
                   m.reason);
      return;
    }
    spdlog::error("EMERGENCY STOP from '{}': {}", m.header.sender, m.reason);
    stop_motion(*gate_.stop_reason(true, ephor::mono_us()));
  }

  // Bus thread.
  void on_servo(const ephor::joint_state_t& m) {
    ephor::arm::ServoState s;
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
    servo_mono_us_ = ephor::mono_us();
    finish_if(monitor_.on_servo(s, ephor::mono_us()));
    deliver();
  }

  // Task "command": validates, plans and sends every queued command in order.
  void command_job() {
    for (;;) {
      ephor::arm_cmd_t m;
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
  void state_job() {
    std::lock_guard<std::mutex> lock(mutex_);
    finish_if(monitor_.on_tick(ephor::mono_us()));
    deliver();
    if (const auto why = gate_.stop_reason(monitor_.busy(), ephor::mono_us())) {
      spdlog::error("{}", *why);
      stop_motion(*why);
    }
    if (!servo_) return;  // nothing known about the arm yet
    const ephor::arm::ToolInField tool = ephor::arm::tool_in_field(cell_, servo_->q);
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
    ephor::arm_state_t s;
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
    bus_.publish(ephor::channels::kArmState, s);
  }

  void log_summary() const {
    spdlog::info(
        "commands: {} accepted, {} rejected, {} sent before this arm started (failed, not "
        "executed), {} repeats answered, {} foreign ignored; trajectories sent again: {}",
        accepted_.load(), rejected_.load(), from_before_start_.load(), repeats_.load(),
        foreign_.load(), resends_.load());
  }

 private:
  ephor::calibration::Plane nearest_plane(double z_mm) const {
    return std::abs(z_mm - cell_.object_plane_z_mm) < std::abs(z_mm - cell_.elevation_plane_z_mm)
               ? ephor::calibration::Plane::kObject
               : ephor::calibration::Plane::kElevation;
  }
  int plane_by_height(double z_mm) const {
    if (std::abs(z_mm - cell_.object_plane_z_mm) < 5.0) return ephor::arm::kPlaneObject;
    if (std::abs(z_mm - cell_.elevation_plane_z_mm) < 5.0) return ephor::arm::kPlaneElevation;
    return -1;
  }

  // Caller holds mutex_.
  void publish_ack(const ArmAck& ack, int64_t cmd_utime) {
    ledger_.record(ack.seq, cmd_utime, ack);
    ephor::arm_ack_t m;
    m.utime = ephor::wall_us();
    m.seq = ack.seq;
    m.goal_id = ack.goal_id;
    m.status = static_cast<int8_t>(ack.status);
    m.reason = ack.reason;
    m.planned_duration_s = static_cast<float>(ack.planned_duration_s);
    bus_.publish(ephor::channels::kArmAck, m);
    if (ack.status == AckStatus::kRejected || ack.status == AckStatus::kFailed) {
      spdlog::warn("seq {} {}: {}", ack.seq, ephor::arm::to_string(ack.status), ack.reason);
    } else {
      spdlog::debug("seq {} {}", ack.seq, ephor::arm::to_string(ack.status));
    }
  }
  // Caller holds mutex_.
  void finish_if(const std::optional<ArmAck>& ack) {
    if (ack) publish_ack(*ack, executing_cmd_utime_);
  }
  // Caller holds mutex_.
  void reject(const ephor::arm_cmd_t& m, std::string reason) {
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
  void fail_unknown(const ephor::arm_cmd_t& m, std::string reason) {
    ArmAck ack;
    ack.seq = m.seq;
    ack.goal_id = m.goal_id;
    ack.status = AckStatus::kFailed;
    ack.reason = std::move(reason);
    ++from_before_start_;
    publish_ack(ack, m.utime);
  }

  void handle_command(const ephor::arm_cmd_t& m) {
    Joints start;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (const auto previous = ledger_.find(m.seq, m.utime)) {
        ++repeats_;
        publish_ack(*previous, m.utime);  // at most once: answer again, do not move again
        return;
      }
      if (const auto why = gate_.refuse_command()) return reject(m, *why);
      const int64_t age_us = ephor::wall_us() - m.utime;
      const auto max_age_us = static_cast<int64_t>(options_.max_age_ms * 1000.0);
      if (m.utime <= 0) return reject(m, "command has no send time (utime <= 0)");
      // Too old or from the future: refused whenever it was first sent (the
      // restart rule below never needs to vouch for it).
      if (age_us > max_age_us)
        return reject(m, fmt::format("stale: sent {:.0f} ms ago (max age {:.0f} ms)", age_us / 1e3,
                                     options_.max_age_ms));
      if (age_us < -max_age_us)
        return reject(m, fmt::format("send time {:.0f} ms in the future: clocks out of sync?",
                                     -age_us / 1e3));
      // Sent before this run began: a restarted arm cannot know whether the
      // run before executed it (CommandLedger), so it never does.
      if (auto why = ledger_.refusal(m.seq, m.utime)) return fail_unknown(m, std::move(*why));
      if (!servo_) return reject(m, "no joint state from the servo yet (ARM_SERVO)");
      const double silent_ms = (ephor::mono_us() - servo_mono_us_) / 1e3;
      if (silent_ms > options_.servo_silence_ms)
        return reject(m, fmt::format("servo silent for {:.0f} ms (ARM_SERVO)", silent_ms));
      start = servo_->q;
    }

    const ephor::arm::ArmCommand cmd = ephor::arm::command_from_message(m);

    // Validate and plan without the lock (OMPL may take its time budget); if
    // the arm moved meanwhile, plan again from where it is now.
    ephor::arm::Validation v;
    ephor::arm::MotionPlan plan;
    for (int attempt = 0; attempt < 3; ++attempt) {
      v = validator_.validate(cmd, start);
      if (v.ok && cmd.kind == ephor::arm::kKindTrajectory) {
        // Executed as given: the validator checked it against the limits.
        plan = ephor::arm::MotionPlan{};
        plan.ok = true;
        plan.kind = ephor::arm::MotionKind::kJointSpace;
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
  void stop_motion(const std::string& why) {
    finish_if(monitor_.abort(why));
    if (!servo_) return;  // never heard the servo: nothing was sent to it
    publish_trajectory(ephor::arm::controlled_stop(servo_->q, servo_->qd, arm_.limits()),
                       /*stop=*/true);
  }

  // Sends the last trajectory again when the servo has not taken it up
  // (TrajectoryDelivery: a lost datagram). Caller holds mutex_.
  void deliver() {
    if (!servo_) return;
    const int64_t now = ephor::mono_us();
    switch (delivery_.check(*servo_, now)) {
      case ephor::arm::TrajectoryDelivery::Action::kNone:
        return;
      case ephor::arm::TrajectoryDelivery::Action::kResend: {
        bus_.publish(ephor::channels::kArmTrajectory, last_trajectory_);
        delivery_.resent(now);
        const int64_t n = ++resends_;
        if (n <= 10 || n % 100 == 0)
          spdlog::warn("trajectory {} not taken up by the servo (lost?): sent again ({} so far)",
                       last_trajectory_.seq, n);
        return;
      }
      case ephor::arm::TrajectoryDelivery::Action::kReplanStop: {
        const int64_t n = ++resends_;
        if (n <= 10 || n % 100 == 0)
          spdlog::warn(
              "stop trajectory {} not taken up by the servo (lost?): stopping again "
              "from where the arm is ({} so far)",
              last_trajectory_.seq, n);
        publish_trajectory(ephor::arm::controlled_stop(servo_->q, servo_->qd, arm_.limits()),
                           /*stop=*/true);
        return;
      }
      case ephor::arm::TrajectoryDelivery::Action::kGiveUp:
        ++resends_;
        finish_if(monitor_.abort(delivery_.why()));
        return;
    }
  }

  // Caller holds mutex_. Returns the trajectory's seq. `stop`: a controlled
  // stop (sent again from where the arm is if lost), else a motion.
  int64_t publish_trajectory(const ephor::arm::Trajectory& trajectory, bool stop) {
    ephor::joint_trajectory_t t;
    t.utime = ephor::wall_us();
    t.seq = ++next_trajectory_seq_;
    t.num_points = static_cast<int32_t>(trajectory.points.size());
    for (const auto& p : trajectory.points) {
      t.t_s.push_back(static_cast<float>(p.t_s));
      t.q.emplace_back(p.q.data(), p.q.data() + 6);
      t.qd.emplace_back(p.qd.data(), p.qd.data() + 6);
    }
    bus_.publish(ephor::channels::kArmTrajectory, t);
    const Joints first = !trajectory.points.empty() ? trajectory.points.front().q
                         : servo_                   ? servo_->q
                                                    : Joints::Zero();
    delivery_.sent(t.seq, first, stop, ephor::mono_us());
    last_trajectory_ = std::move(t);
    return last_trajectory_.seq;
  }

  // Caller holds mutex_.
  void send(const ephor::arm_cmd_t& m, const ephor::arm::Validation& v,
            const ephor::arm::MotionPlan& plan) {
    finish_if(monitor_.preempt(m.seq));
    const int64_t trajectory_seq = publish_trajectory(plan.trajectory, /*stop=*/false);
    monitor_.set_plane(m.plane);
    monitor_.start(m.seq, m.goal_id, trajectory_seq, plan.goal_q, plan.trajectory.duration_s(),
                   ephor::mono_us());
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
        m.seq, m.goal_id,
        m.kind == ephor::arm::kKindTrajectory ? "given trajectory"
                                              : ephor::arm::to_string(plan.kind),
        v.target.tip_mm.x(), v.target.tip_mm.y(), v.target.tip_mm.z(), plan.trajectory.duration_s(),
        plan.speed_scale,
        plan.cartesian_rejected.empty()
            ? ""
            : " (straight line not possible: " + plan.cartesian_rejected + ")");
  }

  ephor::Bus& bus_;
  ephor::TaskRuntime& runtime_;
  ephor::geometry::Workcell cell_;
  Options options_;
  ephor::arm::Puma560 arm_;
  ephor::arm::CommandValidator validator_;
  ephor::calibration::FieldCalibration calibration_;
  ephor::arm::MotionPlanner planner_;

  std::mutex queue_mutex_;
  std::deque<ephor::arm_cmd_t> queue_;

  std::mutex mutex_;  // everything below
  std::optional<ephor::arm::ServoState> servo_;
  int64_t servo_mono_us_ = 0;
  ephor::arm::CommandLedger ledger_;
  ephor::arm::ExecutionMonitor monitor_;
  ephor::arm::SafetyGate gate_;
  int64_t executing_cmd_utime_ = 0;
  int64_t next_trajectory_seq_;
  ephor::arm::TrajectoryDelivery delivery_;
  ephor::joint_trajectory_t last_trajectory_;

  std::atomic<int64_t> accepted_{0}, rejected_{0}, repeats_{0}, foreign_{0}, bad_servo_{0},
      from_before_start_{0}, resends_{0};
};

}  // namespace

int main(int argc, char** argv) {
  ephor::block_shutdown_signals();
  CLI::App app{"ephor-arm: PUMA 560 manipulation process (image targets -> IK -> trajectories)"};
  ephor::ProcessArgs args;
  ephor::add_process_flags(app, args, "arm");
  Options options;
  std::string calibration_path;
  std::string workcell_path;
  double duration_s = 0.0;
  app.add_option("--calibration", calibration_path,
                 "calibration file (default: deploy/calibration/sim.pbtxt of the repository)");
  app.add_option("--workcell", workcell_path,
                 "work cell file (common/geometry/workcell.proto; default: the shepherding field)");
  app.add_option("--max-speed-mm-s", options.max_speed_mm_s,
                 "tool speed cap and default, mm/s (default 300; the joint limits always hold)")
      ->check(CLI::Range(1.0, 10000.0));
  app.add_option("--max-age-ms", options.max_age_ms,
                 "refuse commands sent longer ago than this, ms (default 500)")
      ->check(CLI::Range(1.0, 600000.0));
  app.add_option("--accept-from", options.accept_from,
                 "the only sender (header.sender) whose commands are executed (default comm)");
  app.add_option("--comm-timeout-ms", options.comm_timeout_ms,
                 "stop a motion when nothing has been heard from the commanding sender for this "
                 "long, ms (comm polls every 200 ms while a motion runs; 0 = never; default 1000)")
      ->check(CLI::Range(0.0, 600000.0));
  app.add_option("--duration", duration_s, "exit after this many seconds (0 = until signalled)");
  if (const auto exit_status = ephor::parse_flags(app, argc, argv)) return *exit_status;
  ephor::init_logging(args.name);

  try {
    if (calibration_path.empty()) calibration_path = ephor::default_calibration_path();
    const ephor::geometry::Workcell cell = ephor::geometry::workcell_from_flag(workcell_path);
    if (!workcell_path.empty()) spdlog::info("work cell {}", workcell_path);
    const ephor::geometry::OverheadCamera camera;
    auto calibration = ephor::calibration::FieldCalibration::load(calibration_path);
    spdlog::info("calibration {}", calibration_path);

    ephor::Bus bus(args.lcm_url, args.name);
    ephor::TaskRuntime runtime(bus, {args.name, args.host, !args.no_mlock});
    ArmProcess arm(bus, runtime, cell, std::move(calibration), camera, options);
    bus.subscribe<ephor::arm_cmd_t>(ephor::channels::kArmCmd,
                                    [&arm](const ephor::arm_cmd_t& m) { arm.on_command(m); });
    bus.subscribe<ephor::estop_t>(ephor::channels::kEstop,
                                  [&arm](const ephor::estop_t& m) { arm.on_estop(m); });
    bus.subscribe<ephor::joint_state_t>(ephor::channels::kArmServo,
                                        [&arm](const ephor::joint_state_t& m) { arm.on_servo(m); });
    runtime.add_periodic("state", std::chrono::milliseconds(10), [&arm] { arm.state_job(); });
    runtime.add_triggered("command", std::chrono::seconds(1), [&arm] { arm.command_job(); });
    runtime.start();
    spdlog::info(
        "ready: max speed {:.0f} mm/s, max command age {:.0f} ms, accepting from '{}', comm "
        "timeout {:.0f} ms, ESTOP obeyed from anyone",
        options.max_speed_mm_s, options.max_age_ms, options.accept_from, options.comm_timeout_ms);
    ephor::wait_for_shutdown_signal(duration_s);
    runtime.stop();
    arm.log_summary();
  } catch (const ephor::ConfigError& e) {
    // A file given on the command line is bad: one line, status 2 (issue 18).
    std::cerr << "ephor-arm: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
  return 0;
}
