#pragma once
// JointPathTiming: near time-optimal timing of a joint-space polyline (from
// JointSpacePlanner) under the joint velocity and acceleration limits and the
// tool-speed cap. Each straight segment is travelled from rest to rest; along
// it the path speed follows the classic velocity-limit-curve construction
// (forward pass accelerating, backward pass braking): where the tool sweeps
// fast (arm stretched out) the motion slows, elsewhere it runs at the joints'
// limits. Uniform slowing (the paper's rule, used for Cartesian moves) would
// let the single fastest tool point set the pace of the whole motion.
//
// On a straight joint segment q(s) = w_k + s (w_k+1 - w_k), so joint
// accelerations are exactly (w_k+1 - w_k) s'' and bounding s'' bounds them.

#include <vector>

#include "common/arm/puma560.h"

namespace ephor::arm {

class JointPathTiming {
 public:
  // waypoints: at least one, within limits. tool_speed_cap_mm_s > 0.
  // limit_fraction: share of the joint limits used (0, 1].
  JointPathTiming(const Puma560& arm, std::vector<Joints> waypoints, double tool_speed_cap_mm_s,
                  double limit_fraction = 0.95);

  double duration_s() const { return t_.empty() ? 0.0 : t_.back(); }
  // Joints at time t (clamped to [0, duration]).
  Joints at(double t_s) const;

 private:
  std::vector<Joints> waypoints_;
  // One entry per grid point of all segments, in time order.
  std::vector<double> t_;     // s
  std::vector<double> s_;     // segment parameter in [0, 1]
  std::vector<double> v_;     // ds/dt, 1/s
  std::vector<int> segment_;  // index of the segment of the grid point
};

}  // namespace ephor::arm
