#pragma once
// ephor-sim's bus handlers and its physics task (out of main.cc, so that the
// fuzz target sim_messages_fuzz.cc runs what the process runs):
// ARM_TRAJECTORY (joint_trajectory_t) as the trajectory the servo task
// applies next, SIM_CMD (shepherd_sim_cmd_t: herd size; world reset with a
// seed on the rising edge of `reset` or a new seed while it is set) and
// SIM_TOOL_LIGHT (shepherd_tool_light_t) applied to the Simulator, the
// physics task's catch-up with the clock, and the GROUND_TRUTH
// (shepherd_ground_truth_t) of a rendered frame.
//
// Threading: the counters are atomic (the bus thread writes them, the exit
// summary reads them); on_trajectory() needs no lock; on_command(),
// on_tool_light() and advance_to() need the caller to hold the lock that
// guards the Simulator (it is not thread-safe).

#include <atomic>
#include <cstdint>
#include <optional>

#include "common/arm/arm_servo.h"
#include "common/shepherd/sim/simulator.h"
#include "ephor/joint_trajectory_t.hpp"
#include "ephor/shepherd_ground_truth_t.hpp"
#include "ephor/shepherd_sim_cmd_t.hpp"
#include "ephor/shepherd_tool_light_t.hpp"

namespace ephor::sim {

// 1 ms steps: the camera renders the world at most 1 ms older than its
// capture time stamp (4 ms steps made frames up to 4 ms stale).
inline constexpr double kPhysicsStepS = 0.001;
// Beyond this the simulation skips ahead instead of catching up, s.
inline constexpr double kMaxLagS = 0.5;
// SIM_CMD's herd size is refused outside [0, kMaxSheep] (--sheep's range).
inline constexpr int32_t kMaxSheep = 64;

class SimInputs {
 public:
  // ARM_TRAJECTORY: the trajectory for the servo task to apply next, or
  // nullopt for a malformed one (to_trajectory(): logged and counted).
  std::optional<JointTrajectory> on_trajectory(const joint_trajectory_t& m);
  // SIM_CMD: false (logged, counted, nothing changed) for a herd size outside
  // [0, kMaxSheep].
  bool on_command(const shepherd_sim_cmd_t& m, Simulator& sim);
  // SIM_TOOL_LIGHT: the calibration light on or off (a change is logged).
  void on_tool_light(const shepherd_tool_light_t& m, Simulator& sim);

  int64_t trajectories_received() const { return trajectories_received_; }
  int64_t trajectories_refused() const { return trajectories_refused_; }
  int64_t commands_refused() const { return commands_refused_; }

 private:
  // SIM_CMD edge detection.
  bool last_reset_ = false;
  int32_t last_seed_ = 0;
  int32_t last_sheep_ = -1;
  std::atomic<int64_t> trajectories_received_{0}, trajectories_refused_{0}, commands_refused_{0};
};

// The physics task: steps `sim` in kPhysicsStepS steps from `clock_s` (the
// simulated time since start-up, s; advanced here) up to `now_s`; more than
// kMaxLagS behind (a debugger, overload), it skips ahead instead of running a
// burst (logged) and returns true.
bool advance_to(Simulator& sim, double& clock_s, double now_s);

// The GROUND_TRUTH of a frame rendered at `utime` (wall clock, us).
shepherd_ground_truth_t ground_truth_message_of(const GroundTruth& gt, int64_t utime,
                                                int64_t frame_index);

}  // namespace ephor::sim
