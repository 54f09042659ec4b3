#pragma once
// ephor-catch-prim's messages in and out, as its plan task converts them
// (out of main.cc, so that the fuzz target prim_messages_fuzz.cc runs what
// the process runs): a CATCH_WORLD as the planner's prediction, an
// ARM_STATE as the cup's place, a goal as the ARM_GOAL it publishes.

#include <cstdint>
#include <optional>

#include <Eigen/Core>

#include "common/catch/prim/catch_planner.h"
#include "ephor/arm_goal_t.hpp"
#include "ephor/arm_state_t.hpp"
#include "ephor/catch_world_t.hpp"

namespace ephor::catching {

// The world model's prediction, or nullopt when the frame has none (no ball,
// no prediction) or when its catch point or sigma is not finite (*bad set:
// counted, not chased).
std::optional<CatchPrediction> prediction_of(const catch_world_t& world, bool* bad);

// The tool's place (W, mm), or nullopt when it is not finite.
std::optional<Eigen::Vector3d> cup_of(const arm_state_t& state);

// A pose goal for the cup at the goal's point, the arm's own speed cap; its
// goal id offset by the run's start (wall clock, us) so that ids stay unique
// across restarts. utime is the caller's to set.
arm_goal_t goal_message_of(const CatchGoal& goal, const catch_world_t& world, int64_t run_id);

}  // namespace ephor::catching
