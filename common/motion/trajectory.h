#pragma once
// A time-parameterised joint trajectory for the servo layer: points from the
// start of execution (t = 0) at a fixed sample period, joints in rad and
// joint velocities in rad/s, PUMA 560 order. Starts and ends at rest.

#include <vector>

#include "common/arm/puma560.h"

namespace ephor::arm {

struct TrajectoryPoint {
  double t_s = 0.0;            // from the start of execution, s
  Joints q = Joints::Zero();   // rad
  Joints qd = Joints::Zero();  // rad/s
};

struct Trajectory {
  std::vector<TrajectoryPoint> points;

  double duration_s() const { return points.empty() ? 0.0 : points.back().t_s; }
  bool empty() const { return points.empty(); }
};

}  // namespace ephor::arm
