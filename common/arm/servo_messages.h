#pragma once
// The simulated servo layer (ArmServo) on the bus: what every system's
// simulator does with ARM_TRAJECTORY (joint_trajectory_t, from ephor-arm) and
// publishes as ARM_SERVO (joint_state_t).

#include <cstdint>
#include <optional>
#include <string>

#include "common/arm/arm_servo.h"
#include "ephor/joint_state_t.hpp"
#include "ephor/joint_trajectory_t.hpp"

namespace ephor::sim {

// joint_trajectory_t -> JointTrajectory; nullopt (and `why`) when its sizes
// do not match or it is malformed (ephor::sim::malformed). Never throws.
std::optional<JointTrajectory> to_trajectory(const joint_trajectory_t& m, std::string& why);

// The servo's state as joint_state_t stamped `utime` (wall clock of the state, us).
joint_state_t to_joint_state(const ServoState& s, int64_t utime);

}  // namespace ephor::sim
