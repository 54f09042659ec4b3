// Fuzz target (issue 18): ephor-rambo-planner on any interleaved stream of
// RAMBO_PREDICTION (rambo_prediction_t), RAMBO_INDICATOR (rambo_indicator_t)
// and ARM_STATE (arm_state_t) with its clock, as its handlers and plan task
// take them (planner_task.h): each message decoded the way the bus does (a
// message that does not decode to its full size is dropped) and handed to
// PlannerTask::on_prediction() (motion_from_message), on_indicator() or
// on_arm_state(), and the plan task's periods, PlannerTask::period(), on a
// wall clock that moves by 0-16.8 s a period, with the process's defaults (the
// built-in target, lead 0.3 s, prediction ages 3 s and 8 s, 0.8 of the
// limits) and --diodes 1-4 and --reach trajectory or goals from the input.
// Every goal it would send must be finite and within the PUMA's joint limits
// as the planner plans with them (PlannerTask::limits(): every position
// within q_min..q_max and, for a trajectory, every speed within qd_max,
// times from 0 increasing), and the goal and the RAMBO_PLAN must encode.
//
// Input: a byte of settings (bit 0: --reach goals; bits 1-2: --diodes 1-4),
// then up to 96 records, each a byte naming what comes (bits 0-1: 0
// RAMBO_PREDICTION, 1 RAMBO_INDICATOR, 2 ARM_STATE, 3 a plan period), then
// for a message a 2-byte length (little-endian) and that many bytes, for a
// period 2 bytes of clock step (little-endian, x 256 us) before it. At most
// 4 periods an input (at 8, 6 inputs/s): a period may order the open diodes
// (greedy, exhaustive and DP over reaching trajectories) and plan a reaching
// trajectory, work the process bounds only by its period. Seeds: fuzz_corpus/rambo_planner (the arm
// at its start pose, the target tumbling slowly 900 mm out, predicted, the
// first diode tagged at the third period; the prediction going stale; made
// by a small generator).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <spdlog/spdlog.h>

#include "common/fuzz/fuzz_input.h"
#include "common/rambo/rambo_cell.h"
#include "common/rambo/target_model_file.h"
#include "procs/rambo/planner/planner_task.h"

namespace {

using namespace ephor;
using namespace ephor::rambo;

constexpr double kTolRad = 1e-6;

void check_joints(const arm::JointLimits& lim, const double* q, const char* what) {
  for (int j = 0; j < 6; ++j) {
    if (!std::isfinite(q[j])) fuzz::fail(std::string(what) + ": a joint that is not finite");
    if (q[j] < lim.q_min[j] - kTolRad || q[j] > lim.q_max[j] + kTolRad)
      fuzz::fail(std::string(what) + ": joint " + std::to_string(j + 1) + " at " +
                 std::to_string(q[j]) + " rad, outside its limits");
  }
}

void check(const PlannerTask& task, const PlannerTask::Period& p) {
  fuzz::check_encodes(p.plan, "the plan");
  if (!std::isfinite(p.plan.order_total_s)) fuzz::fail("a plan's order time that is not finite");
  if (!p.goal) return;
  const arm_goal_t& g = *p.goal;
  const arm::JointLimits& lim = task.limits();
  check_joints(lim, g.joints_rad, "the goal's joints");
  if (g.kind == arm_goal_t::KIND_TRAJECTORY) {
    if (g.num_points < 1 || static_cast<int>(g.traj_t_s.size()) != g.num_points ||
        static_cast<int>(g.traj_q_rad.size()) != g.num_points ||
        static_cast<int>(g.traj_qd_rad_s.size()) != g.num_points)
      fuzz::fail("a trajectory whose sizes disagree");
    for (int k = 0; k < g.num_points; ++k) {
      const auto i = static_cast<size_t>(k);
      if (!std::isfinite(g.traj_t_s[i]) || (k == 0 && g.traj_t_s[i] != 0.0f) ||
          (k > 0 && !(g.traj_t_s[i] > g.traj_t_s[i - 1])))
        fuzz::fail("a trajectory's times are not 0, increasing");
      check_joints(lim, g.traj_q_rad[i].data(), "a trajectory point");
      for (int j = 0; j < 6; ++j) {
        const double qd = g.traj_qd_rad_s[i][static_cast<size_t>(j)];
        if (!std::isfinite(qd) || std::abs(qd) > lim.qd_max[j] + kTolRad)
          fuzz::fail("a trajectory point: joint " + std::to_string(j + 1) + " speed " +
                     std::to_string(qd) + " rad/s, above its limit");
      }
    }
    for (int j = 0; j < 6; ++j)
      if (g.joints_rad[j] != g.traj_q_rad.back()[static_cast<size_t>(j)])
        fuzz::fail("a trajectory's goal joints are not its last point");
  } else if (g.kind != arm_goal_t::KIND_JOINTS) {
    fuzz::fail("a goal of a kind the planner does not send");
  }
  fuzz::check_encodes(g, "the goal");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  // The task's log lines (a new status, a re-fit) would only slow the run.
  static const bool quiet = [] {
    spdlog::set_level(spdlog::level::off);
    return true;
  }();
  (void)quiet;
  if (size < 1) return 0;
  PlannerTaskOptions options;
  options.reach_trajectory = (data[0] & 1) == 0;
  options.diodes = 1 + ((data[0] >> 1) & 3);
  static const RamboCell cells[4] = {cell_from_flags("", 1), cell_from_flags("", 2),
                                     cell_from_flags("", 3), cell_from_flags("", 4)};
  const RamboCell& cell = cells[options.diodes - 1];
  int64_t now_us = 1'700'000'000'000'000;
  PlannerTask task(cell, options, now_us);
  const auto clock = [&now_us] { return now_us; };
  size_t at = 1;
  int periods = 0;
  for (int k = 0; k < 96 && at < size; ++k) {
    const int what = data[at] & 3;
    ++at;
    if (at + 2 > size) break;
    const size_t word = data[at] | (static_cast<size_t>(data[at + 1]) << 8);
    at += 2;
    if (what == 3) {
      if (++periods > 4) break;
      now_us += 256 * static_cast<int64_t>(word);
      check(task, task.period(clock));
      continue;
    }
    if (word > size - at) break;
    const int n = static_cast<int>(word);
    const uint8_t* bytes = data + at;
    at += word;
    if (what == 0) {
      rambo_prediction_t m;
      if (m.decode(bytes, 0, n) != n) continue;
      std::string why;
      task.on_prediction(m, &why);
    } else if (what == 1) {
      rambo_indicator_t m;
      if (m.decode(bytes, 0, n) != n) continue;
      task.on_indicator(m);
    } else {
      arm_state_t m;
      if (m.decode(bytes, 0, n) != n) continue;
      task.on_arm_state(m);
    }
  }
  return 0;
}
