#include "procs/shared/arm/controlled_stop.h"

#include <algorithm>
#include <cmath>

namespace ephor::arm {

Trajectory controlled_stop(const Joints& q, const Joints& qd, const JointLimits& limits,
                           const ControlledStopConfig& config) {
  // A velocity beyond the joint's limit is planned as the limit: the servo
  // never moves a joint faster, and a reported 1e300 rad/s (any finite
  // joint_state_t passes) made the stop last 6e299 s, infinite as the
  // message's float time (fuzz target arm_process).
  Joints v;
  for (int j = 0; j < 6; ++j) v(j) = std::clamp(qd(j), -limits.qd_max(j), limits.qd_max(j));
  // The joint that needs longest to stop sets the time for all of them.
  double t_s = config.min_duration_s;
  for (int j = 0; j < 6; ++j) {
    const double decel = config.deceleration_fraction * limits.qdd_max(j);
    if (decel > 0.0) t_s = std::max(t_s, std::abs(v(j)) / decel);
  }
  TrajectoryPoint end;
  end.t_s = t_s;
  for (int j = 0; j < 6; ++j) {
    end.q(j) = std::clamp(q(j) + 0.5 * v(j) * t_s, limits.q_min(j), limits.q_max(j));
  }
  end.qd = Joints::Zero();
  Trajectory stop;
  stop.points.push_back(end);
  return stop;
}

}  // namespace ephor::arm
