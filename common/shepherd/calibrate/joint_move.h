#pragma once
// JointMove: a slow point-to-point move in joint space for the servo layer
// (joint_trajectory_t), as a teach pendant would make it: every joint follows
// the same trapezoidal velocity profile in time (a third accelerating, a third
// cruising, a third braking), so all joints start and stop together, and the
// duration is the shortest for which no joint exceeds `speed_fraction` of its
// velocity and acceleration limits.
//
// Units: rad, rad/s, s; PUMA 560 joint order (common/arm/puma560.h).

#include <vector>

#include "common/arm/puma560.h"

namespace ephor::calibrate {

struct JointPath {
  std::vector<double> t_s;      // from the start of execution, s, strictly increasing, t_s[0] = 0
  std::vector<arm::Joints> q;   // rad
  std::vector<arm::Joints> qd;  // rad/s
  double duration_s() const { return t_s.empty() ? 0.0 : t_s.back(); }
};

class JointMove {
 public:
  // from -> to (both within `limits`), sampled every <= sample_s seconds.
  // speed_fraction in (0, 1]. Throws std::invalid_argument for non-finite
  // joints, joints outside the limits or a bad fraction or sample time.
  static JointPath plan(const arm::Joints& from, const arm::Joints& to,
                        const arm::JointLimits& limits, double speed_fraction = 0.5,
                        double sample_s = 0.05);
};

}  // namespace ephor::calibrate
