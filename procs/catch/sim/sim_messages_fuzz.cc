// Fuzz target (issue 18): ephor-catch-sim (CatchSimProcess, sim_messages.h)
// on any stream of ARM_TRAJECTORY messages, its only input, with its tasks
// released as the runtime would: each message decoded as the bus does (one
// that does not decode to its full size is dropped) and handed to
// on_trajectory(); the task "physics" at every 2 ms boundary of a fake
// monotonic clock advanced by each record's step (advance_to(), and the
// ARM_SERVO of every second run), the task "camera" on a record of
// channel 1 (the CATCH_TRUTH of that moment). The world is the process's
// with the deployed board and work cell (deploy/catch/), --seed 1, endless
// balls, --gap-s 0.2 and --first-release-s 0.5 (within the flags' ranges:
// balls roll, fly and are judged while the arm follows what it is sent). A
// run simulates at most 6 s (the physics' 1 ms steps dominate a run).
//
// Checked: a trajectory refused is counted once in trajectories_refused and
// leaves the pending one as it was; one taken is pending with its seq and
// points; the servo's joints stay finite, within the PUMA 560's position
// limits and its velocities within qd_max whatever it was sent; ARM_SERVO
// and CATCH_TRUTH are finite (but ball_px, NaN until the renderer fills it
// in), counts consistent (caught <= judged), and both encode.
//
// Input: a FuzzMessageStream (common/fuzz/fuzz_input.h) of up to 256
// messages of up to 4096 bytes; channels 0 ARM_TRAJECTORY
// (joint_trajectory_t), 1 run the camera task. Seeds: fuzz_corpus/catch_sim
// (the arm sent from park to the ready point and then on a catch move;
// trajectories with a point out of the limits, too fast, with a NaN, with
// arrays of the wrong size, a duplicate seq, one replaced while pending).
//
// The process's log is off; CATCH_SIM_FUZZ_TRACE=1 in the environment turns
// it on and prints the park and ready joints and, at the end of each input,
// the servo's state and the balls judged (for writing seeds).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <spdlog/fmt/fmt.h>
#include <spdlog/spdlog.h>

#include "common/catch/board_file.h"
#include "common/catch/sim/catch_scenario.h"
#include "common/config/repo_paths.h"
#include "common/fuzz/fuzz_input.h"
#include "common/geometry/workcell_file.h"
#include "procs/catch/sim/sim_messages.h"

namespace {

using namespace ephor;
using namespace ephor::catching;

constexpr int64_t kPhysicsPeriodUs = 2'000;     // task "physics"
constexpr int64_t kMaxSimulatedUs = 6'000'000;  // per input

void check_servo(const CatchSimProcess& p) {
  const sim::ServoState& s = p.servo.state();
  const arm::JointLimits& limits = p.servo.limits();
  for (int j = 0; j < 6; ++j) {
    if (!std::isfinite(s.q(j)) || !std::isfinite(s.qd(j)))
      fuzz::fail(fmt::format("joint {}: servo state not finite", j + 1));
    if (s.q(j) < limits.q_min(j) - 1e-9 || s.q(j) > limits.q_max(j) + 1e-9)
      fuzz::fail(fmt::format("joint {}: {} rad outside [{}, {}] rad", j + 1, s.q(j),
                             limits.q_min(j), limits.q_max(j)));
    if (std::abs(s.qd(j)) > limits.qd_max(j) * (1.0 + 1e-9))
      fuzz::fail(fmt::format("joint {}: {} rad/s above its limit {} rad/s", j + 1, s.qd(j),
                             limits.qd_max(j)));
  }
}

void check_servo_message(const joint_state_t& m) {
  if (!fuzz::all_finite(m.q, 6) || !fuzz::all_finite(m.qd, 6))
    fuzz::fail("an ARM_SERVO that is not finite");
  fuzz::check_encodes(m, "ARM_SERVO");
}

void check_truth(const catch_truth_t& m) {
  if (!fuzz::all_finite(m.ball_b_mm, 3) || !fuzz::all_finite(m.ball_w_mm, 3) ||
      !fuzz::all_finite(m.ball_velocity_b_mm_s, 2) || !fuzz::all_finite(m.cup_w_mm, 3) ||
      !std::isfinite(m.exit_x_b_mm) || !std::isfinite(m.incline_deg) ||
      !fuzz::all_finite(m.board_to_camera_r, 9) || !fuzz::all_finite(m.board_to_camera_t_mm, 3))
    fuzz::fail("a CATCH_TRUTH that is not finite");
  if (m.phase < catch_truth_t::PHASE_WAITING || m.phase > catch_truth_t::PHASE_DONE)
    fuzz::fail("a CATCH_TRUTH phase out of range");
  if (m.caught < 0 || m.caught > m.balls_done || m.oracle_reachable > m.balls_done)
    fuzz::fail(fmt::format("CATCH_TRUTH counts: {} judged, {} caught, {} reachable", m.balls_done,
                           m.caught, m.oracle_reachable));
  fuzz::check_encodes(m, "CATCH_TRUTH");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const BoardSpec board = [] {
    spdlog::set_level(spdlog::level::off);  // the process's log (a warning per refusal)
    return load_board_file(resolve_repo_path("deploy/catch/board.pbtxt"));
  }();
  static const geometry::Workcell cell =
      geometry::load_workcell_file(resolve_repo_path("deploy/catch/workcell.pbtxt"));
  static const CatchScenario scenario = CatchScenario::draw(1, board);

  CatchSimProcess p(scenario, cell, 0, 0.2, 0.5);
  static const bool trace = [&p] {
    const bool on = std::getenv("CATCH_SIM_FUZZ_TRACE") != nullptr;
    if (on) {
      const arm::Joints park = p.catch_cell.park_joints(), ready = p.catch_cell.ready_joints();
      std::fprintf(stderr,
                   "park %.6f %.6f %.6f %.6f %.6f %.6f\nready %.6f %.6f %.6f %.6f %.6f %.6f\n",
                   park(0), park(1), park(2), park(3), park(4), park(5), ready(0), ready(1),
                   ready(2), ready(3), ready(4), ready(5));
      spdlog::set_level(spdlog::level::info);
    }
    return on;
  }();
  p.wall0_us = 1'700'000'000'000'000;
  int64_t mono_us = 0, next_physics_us = kPhysicsPeriodUs;

  fuzz::FuzzMessageStream stream(data, size, 2);
  fuzz::FuzzMessage msg;
  while (stream.next(msg) && mono_us + msg.step_us <= kMaxSimulatedUs) {
    mono_us += msg.step_us;
    for (; next_physics_us <= mono_us; next_physics_us += kPhysicsPeriodUs) {
      std::lock_guard<std::mutex> lock(p.mutex);
      p.advance_to(static_cast<double>(next_physics_us) * 1e-6);
      check_servo(p);
      if (++p.servo_ticks % 2 == 0) check_servo_message(p.servo_message());
    }
    if (msg.channel == 1) {
      std::lock_guard<std::mutex> lock(p.mutex);
      check_truth(p.truth());
      continue;
    }
    joint_trajectory_t m;
    if (!msg.decode(m)) continue;  // the bus counts a decode error
    const int64_t refused_before = p.trajectories_refused;
    std::optional<int64_t> pending_before;
    if (p.pending) pending_before = p.pending->seq;
    if (p.on_trajectory(m)) {
      if (p.trajectories_refused != refused_before) fuzz::fail("a trajectory taken and counted");
      if (!p.pending || p.pending->seq != m.seq ||
          p.pending->t_s.size() != static_cast<size_t>(m.num_points))
        fuzz::fail("a trajectory taken but not the one pending");
    } else {
      if (p.trajectories_refused != refused_before + 1)
        fuzz::fail("a trajectory refused uncounted");
      if (p.pending.has_value() != pending_before.has_value() ||
          (p.pending && p.pending->seq != *pending_before))
        fuzz::fail("a refused trajectory changed the pending one");
    }
  }
  std::lock_guard<std::mutex> lock(p.mutex);
  const catch_truth_t truth = p.truth();
  check_truth(truth);
  if (trace)
    std::fprintf(stderr,
                 "%.3f s: %lld refused, servo following seq %lld%s%s; %d balls judged, %d "
                 "caught\n",
                 p.clock_s, static_cast<long long>(p.trajectories_refused.load()),
                 static_cast<long long>(p.servo.state().trajectory_seq),
                 p.servo.state().fault ? ", fault: " : "", p.servo.state().fault_reason.c_str(),
                 truth.balls_done, truth.caught);
  return 0;
}
