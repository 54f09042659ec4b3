// Fuzz target (issue 18): ephor-arm itself (ArmProcess, arm_process.h) on any
// interleaved stream of ARM_CMD, ESTOP and ARM_SERVO messages, with its tasks
// released as the runtime would: each message decoded as the bus does (one
// that does not decode to its full size is dropped) and handed to its
// handler; the task "state" run at every 10 ms boundary of a fake clock
// (monotonic and wall, both advanced by each record's step), the task
// "command" when an ARM_CMD released it and the clock next moves (messages
// with step 0 arrive while the command is still queued) or on a record of
// channel 3. Commands are validated, planned (OMPL with a 50 ms budget, not
// the process's 500 ms) and sent as the process does; at most 2 distinct
// commands (seq, utime) from the trusted sender ("comm") are fed per input
// (their repeats too, answered from the ledger): planning dominates a run
// (4 commands: 5 runs/s under ASan), and two already replace, repeat and
// meet an ESTOP in every order.
//
// Checked on everything ArmProcess publishes:
//  - ARM_TRAJECTORY: at least one point, arrays num_points long, times finite
//    and increasing; every position finite and within the PUMA 560's joint
//    limits (Puma560::limits() of the work cell's arm, rad); every velocity
//    finite and within qd_max (rad/s, the validator's relative slack 1e-6),
//    and the mean velocity between neighbouring points within qd_max (the
//    servo's slack, 0.1 %: the servo faults above it); a stop is one point at
//    rest; after an ESTOP with stop = true and until a release, nothing but
//    stops (ArmOutputs::publish_trajectory's `stop`);
//  - ARM_ACK: its (seq, goal id) one that "comm" commanded, a known status,
//    a finite planned duration;
//  - ARM_STATE: every number finite.
//
// Input: a FuzzMessageStream (common/fuzz/fuzz_input.h) of up to 256
// messages of up to 4096 bytes; channels 0 ARM_CMD (arm_cmd_t), 1 ESTOP
// (estop_t), 2 ARM_SERVO (joint_state_t), 3 run the command task. The fake
// wall clock starts at 1'700'000'000'000'000 us (the arm's start, so its
// first trajectory is seq 1'700'000'000'000'001). Seeds:
// fuzz_corpus/arm_process: joint_move_done (a joint move executed with servo
// feedback), estop_mid_motion (an ESTOP in the middle of a motion, the stop
// taken up, a command refused while latched, the release),
// given_trajectory_done (a joint trajectory executed as given); found_* are
// the inputs of the faults this target found.
//
// The process's log is off; ARM_PROCESS_FUZZ_TRACE=1 in the environment
// turns it on and prints every published trajectory and ack (for writing
// seeds).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <set>
#include <string>
#include <utility>

#include <spdlog/fmt/fmt.h>
#include <spdlog/spdlog.h>

#include "common/arm/arm_workcell.h"
#include "common/calibration/field_calibration.h"
#include "common/fuzz/fuzz_input.h"
#include "common/geometry/overhead_camera.h"
#include "common/geometry/workcell.h"
#include "procs/shared/arm/arm_process.h"

namespace {

using namespace ephor;

constexpr int64_t kWallStartUs = 1'700'000'000'000'000;  // fake wall clock at the start, us
constexpr int64_t kMonoStartUs = 1'000'000'000;          // fake monotonic clock at the start, us
constexpr int64_t kStatePeriodUs = 10'000;               // task "state"
constexpr size_t kMaxCommands = 2;                       // distinct trusted ARM_CMD fed per input
constexpr double kPlannerBudgetS = 0.05;                 // OMPL's budget per plan, s

struct FakeClock {
  int64_t mono_us = kMonoStartUs;
  int64_t wall_us = kWallStartUs;
};

class CheckingOutputs : public arm::ArmOutputs {
 public:
  CheckingOutputs(const arm::JointLimits& limits, bool trace) : limits_(limits), trace_(trace) {}

  bool estopped = false;  // the latch as the ESTOP messages fed set it
  bool command_released = false;
  std::set<std::pair<int64_t, int64_t>> commanded;  // (seq, goal id) of trusted ARM_CMD

  bool publish_state(arm_state_t& m) override {
    bool finite = std::isfinite(m.x_mm) && std::isfinite(m.y_mm) && std::isfinite(m.z_mm) &&
                  std::isfinite(m.u) && std::isfinite(m.v) && std::isfinite(m.theta_rad) &&
                  std::isfinite(m.speed_mm_s);
    for (int j = 0; j < 6; ++j) finite = finite && std::isfinite(m.q[j]) && std::isfinite(m.qd[j]);
    if (!finite) fuzz::fail("ARM_STATE with a number that is not finite");
    return true;
  }

  bool publish_ack(arm_ack_t& m) override {
    if (trace_)
      std::fprintf(stderr, "ack seq %lld goal %lld status %d %.3f s: %s\n",
                   static_cast<long long>(m.seq), static_cast<long long>(m.goal_id), m.status,
                   static_cast<double>(m.planned_duration_s), m.reason.c_str());
    if (commanded.count({m.seq, m.goal_id}) == 0)
      fuzz::fail(
          fmt::format("ARM_ACK for seq {} goal {}, which was never commanded", m.seq, m.goal_id));
    if (m.status < arm_ack_t::STATUS_ACCEPTED || m.status > arm_ack_t::STATUS_FAILED)
      fuzz::fail(fmt::format("ARM_ACK with unknown status {}", m.status));
    if (!std::isfinite(m.planned_duration_s))
      fuzz::fail("ARM_ACK with a planned duration that is not finite");
    return true;
  }

  bool publish_trajectory(joint_trajectory_t& m, bool stop) override {
    if (trace_) {
      std::fprintf(stderr, "trajectory seq %lld, %d points, %s, %.3f s\n",
                   static_cast<long long>(m.seq), m.num_points, stop ? "stop" : "motion",
                   m.t_s.empty() ? 0.0 : static_cast<double>(m.t_s.back()));
      if (!m.q.empty())
        std::fprintf(stderr, "  last q %.4f %.4f %.4f %.4f %.4f %.4f\n", m.q.back()[0],
                     m.q.back()[1], m.q.back()[2], m.q.back()[3], m.q.back()[4], m.q.back()[5]);
    }
    if (estopped && !stop) fuzz::fail("a motion sent while the emergency stop is latched");
    const auto n = static_cast<size_t>(m.num_points);
    if (m.num_points < 1 || m.t_s.size() != n || m.q.size() != n || m.qd.size() != n)
      fuzz::fail(fmt::format("ARM_TRAJECTORY with {} points and arrays of {}, {}, {}", m.num_points,
                             m.t_s.size(), m.q.size(), m.qd.size()));
    if (stop && n != 1) fuzz::fail("a stop of more than one point");
    for (size_t k = 0; k < n; ++k) {
      if (!std::isfinite(m.t_s[k])) fuzz::fail(fmt::format("point {}: time not finite", k));
      if (k > 0 && !(m.t_s[k] > m.t_s[k - 1]))
        fuzz::fail(fmt::format("point {}: time {} s does not increase", k, m.t_s[k]));
      for (int j = 0; j < 6; ++j) {
        const double q = m.q[k][j], qd = m.qd[k][j];
        if (!std::isfinite(q) || !std::isfinite(qd))
          fuzz::fail(fmt::format("point {} joint {}: not finite", k, j + 1));
        if (q < limits_.q_min[j] || q > limits_.q_max[j])
          fuzz::fail(fmt::format("point {} joint {}: {} rad outside [{}, {}] rad", k, j + 1, q,
                                 limits_.q_min[j], limits_.q_max[j]));
        if (std::abs(qd) > limits_.qd_max[j] * (1.0 + 1e-6))
          fuzz::fail(fmt::format("point {} joint {}: {} rad/s above its limit {} rad/s", k, j + 1,
                                 qd, limits_.qd_max[j]));
        if (stop && qd != 0.0) fuzz::fail("a stop that does not end at rest");
        if (k > 0) {
          const double mean = (q - m.q[k - 1][j]) /
                              (static_cast<double>(m.t_s[k]) - static_cast<double>(m.t_s[k - 1]));
          if (std::abs(mean) > limits_.qd_max[j] * 1.001)
            fuzz::fail(fmt::format("points {}-{} joint {}: mean {} rad/s above its limit {} rad/s",
                                   k - 1, k, j + 1, mean, limits_.qd_max[j]));
        }
      }
    }
    return true;
  }

  void command_queued() override { command_released = true; }

 private:
  arm::JointLimits limits_;
  bool trace_;
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const geometry::Workcell cell;
  static const geometry::OverheadCamera camera;
  static const calibration::FieldCalibration calibration =
      calibration::FieldCalibration::from_camera(camera, cell);
  static const arm::JointLimits limits = arm::make_puma(cell).limits();
  static const bool trace = [] {
    const bool on = std::getenv("ARM_PROCESS_FUZZ_TRACE") != nullptr;
    if (!on) spdlog::set_level(spdlog::level::off);  // the process's log, at every input
    return on;
  }();

  arm::ArmProcessOptions options;
  options.planner_time_budget_s = kPlannerBudgetS;
  FakeClock clock;
  CheckingOutputs out(limits, trace);
  arm::ArmProcess arm(out, cell, calibration, camera, options,
                      {[&clock] { return clock.mono_us; }, [&clock] { return clock.wall_us; }});
  const auto run_command_task = [&] {
    if (!out.command_released) return;
    out.command_released = false;
    arm.command_job();
  };

  int64_t next_state_us = clock.mono_us + kStatePeriodUs;
  std::set<std::pair<int64_t, int64_t>> commands;  // (seq, first-sent utime) fed
  fuzz::FuzzMessageStream stream(data, size, 4);
  fuzz::FuzzMessage msg;
  while (stream.next(msg)) {
    if (msg.step_us > 0) {
      run_command_task();  // released by an ARM_CMD before the clock moved on
      const int64_t end_us = clock.mono_us + msg.step_us;
      for (; next_state_us <= end_us; next_state_us += kStatePeriodUs) {
        clock.wall_us += next_state_us - clock.mono_us;
        clock.mono_us = next_state_us;
        arm.state_job();
      }
      clock.wall_us += end_us - clock.mono_us;
      clock.mono_us = end_us;
    }
    switch (msg.channel) {
      case 0: {
        arm_cmd_t m;
        if (!msg.decode(m)) break;
        if (m.header.sender == options.accept_from) {
          // Repeats (comm's polls) are answered from the ledger: not counted.
          if (commands.count({m.seq, m.utime}) == 0 && commands.size() >= kMaxCommands) break;
          commands.insert({m.seq, m.utime});
          out.commanded.insert({m.seq, m.goal_id});
        }
        arm.on_command(m);
        break;
      }
      case 1: {
        estop_t m;
        if (!msg.decode(m)) break;
        out.estopped = m.stop;  // before: the stop goes out from inside on_estop
        arm.on_estop(m);
        break;
      }
      case 2: {
        joint_state_t m;
        if (msg.decode(m)) arm.on_servo(m);
        break;
      }
      default:
        run_command_task();
        break;
    }
  }
  run_command_task();
  arm.state_job();
  return 0;
}
