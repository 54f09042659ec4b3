#pragma once
// ephor-catch-sim's state and what its handler and tasks do with it (out of
// main.cc, so that the fuzz target sim_messages_fuzz.cc runs what the
// process runs): an ARM_TRAJECTORY (joint_trajectory_t, its only input)
// converted and checked by sim::to_trajectory() and handed to the servo at
// the next physics step, the physics advanced in 1 ms steps to a clock, and
// the ARM_SERVO and CATCH_TRUTH it publishes.
//
// Frames and units: W and B of common/catch/board_model.h, mm, rad, s.
// Threading: the members are guarded by `mutex`; on_trajectory() takes it
// itself (the bus's thread calls it), the other methods expect the caller
// to hold it (the runtime's task threads).

#include <atomic>
#include <cmath>
#include <cstdint>
#include <mutex>
#include <optional>

#include "common/arm/arm_servo.h"
#include "common/catch/sim/ball_sequence.h"
#include "common/catch/sim/board_world.h"
#include "common/catch/sim/catch_cell.h"
#include "common/catch/sim/catch_scenario.h"
#include "common/geometry/workcell.h"
#include "ephor/catch_truth_t.hpp"
#include "ephor/joint_state_t.hpp"
#include "ephor/joint_trajectory_t.hpp"

namespace ephor::catching {

constexpr double kSimStepS = 0.001;  // one physics step, s
constexpr double kSimMaxLagS = 0.5;  // physics further behind the clock skips ahead, s

// The state behind one frame as catch_truth_t (caller holds the mutex):
// everything but utime, exit_utime, frame_index and ball_px (NaN: the
// renderer's to fill in).
catch_truth_t to_truth(const CatchScenario& scenario, const BoardWorld& world,
                       const BallSequence& balls, const CatchCell& cell, const arm::Joints& q);

struct CatchSimProcess {
  std::mutex mutex;
  CatchScenario scenario;
  geometry::Workcell cell;
  CatchCell catch_cell;
  BoardWorld world;
  sim::ArmServo servo;
  std::optional<sim::JointTrajectory> pending;  // taken by the next step()
  BallSequence balls;
  double clock_s = 0.0;  // simulated time, s from start-up
  int64_t wall0_us = 0, mono0_ns = 0;
  int servo_ticks = 0;
  std::atomic<int64_t> frames{0}, trajectories_refused{0}, physics_skips{0};

  // Throws std::runtime_error when the scenario's ready point is out of the
  // arm's reach (CatchCell).
  CatchSimProcess(CatchScenario s, const geometry::Workcell& c, int ball_count, double gap_s,
                  double first_release_s);

  int64_t utime_of(double t_s) const { return wall0_us + std::llround(t_s * 1e6); }

  // The ARM_TRAJECTORY handler: a well-formed trajectory replaces any still
  // pending (true); a malformed one is logged, counted in
  // trajectories_refused and ignored (false). Takes the mutex; never throws.
  bool on_trajectory(const joint_trajectory_t& m);

  // One 1 ms step of board, ball sequence and servo (caller holds mutex).
  void step();

  // Steps up to `now_s` (simulated seconds since start-up); more than
  // kSimMaxLagS behind it skips ahead, logged and counted in physics_skips
  // (caller holds mutex).
  void advance_to(double now_s);

  // ARM_SERVO now (caller holds mutex).
  joint_state_t servo_message() const;

  // CATCH_TRUTH now: to_truth() with utime and exit_utime (caller holds
  // mutex); frame_index and ball_px are the camera task's.
  catch_truth_t truth() const;
};

}  // namespace ephor::catching
