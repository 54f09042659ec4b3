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
// The handlers and tasks are ArmProcess (arm_process.h); this file reads the
// flags, subscribes and registers the tasks.
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

#include <iostream>
#include <string>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include "common/calibration/field_calibration.h"
#include "common/config/repo_paths.h"
#include "common/config/text_proto.h"
#include "common/geometry/overhead_camera.h"
#include "common/geometry/workcell.h"
#include "common/geometry/workcell_file.h"
#include "common/lcm/bus.h"
#include "common/lcm/channels.h"
#include "common/log/log.h"
#include "common/runtime/process_args.h"
#include "common/runtime/task_runtime.h"
#include "ephor/arm_ack_t.hpp"
#include "ephor/arm_cmd_t.hpp"
#include "ephor/arm_state_t.hpp"
#include "ephor/estop_t.hpp"
#include "ephor/joint_state_t.hpp"
#include "ephor/joint_trajectory_t.hpp"
#include "procs/shared/arm/arm_process.h"

namespace {

// ArmProcess's outputs: its messages on the bus, its command task released
// on the task runtime.
class BusOutputs : public ephor::arm::ArmOutputs {
 public:
  BusOutputs(ephor::Bus& bus, ephor::TaskRuntime& runtime) : bus_(bus), runtime_(runtime) {}
  bool publish_state(ephor::arm_state_t& m) override {
    return bus_.publish(ephor::channels::kArmState, m);
  }
  bool publish_ack(ephor::arm_ack_t& m) override {
    return bus_.publish(ephor::channels::kArmAck, m);
  }
  bool publish_trajectory(ephor::joint_trajectory_t& m, bool /*stop*/) override {
    return bus_.publish(ephor::channels::kArmTrajectory, m);
  }
  void command_queued() override { runtime_.trigger("command"); }

 private:
  ephor::Bus& bus_;
  ephor::TaskRuntime& runtime_;
};

}  // namespace

int main(int argc, char** argv) {
  ephor::block_shutdown_signals();
  CLI::App app{"ephor-arm: PUMA 560 manipulation process (image targets -> IK -> trajectories)"};
  ephor::ProcessArgs args;
  ephor::add_process_flags(app, args, "arm");
  ephor::arm::ArmProcessOptions options;
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
    BusOutputs outputs(bus, runtime);
    ephor::arm::ArmProcess arm(outputs, cell, std::move(calibration), camera, options);
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
