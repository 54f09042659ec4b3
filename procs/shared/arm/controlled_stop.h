#pragma once
// controlled_stop: the trajectory that brings a moving PUMA to rest as fast
// as its joints allow (an emergency stop, or comm gone silent). Every joint
// decelerates at a constant rate so that all reach zero velocity together, at
// `deceleration_fraction` of the slowest-to-stop joint's acceleration limit;
// the servo's cubic Hermite between its current state (q, qd) and the one
// point (q + qd T / 2, 0) at time T has exactly that constant deceleration.
// Sent as one point with t = T > 0, so the servo starts from where it really
// is (procs/shepherd/sim ArmServo, like a real servo, prepends its own state).

#include "common/arm/puma560.h"
#include "common/motion/trajectory.h"

namespace ephor::arm {

struct ControlledStopConfig {
  double deceleration_fraction = 0.8;  // of JointLimits::qdd_max
  double min_duration_s = 0.05;        // also the hold time of an arm already at rest
};

// q in rad, qd in rad/s (the newest servo state; each clamped to the
// joint's qd_max, the most the servo commands). The end point is clamped
// into the joint limits.
Trajectory controlled_stop(const Joints& q, const Joints& qd, const JointLimits& limits,
                           const ControlledStopConfig& config = {});

}  // namespace ephor::arm
