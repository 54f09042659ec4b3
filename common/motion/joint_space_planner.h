#pragma once
// JointSpacePlanner: a collision-free joint-space path for the PUMA 560 from
// OMPL (RRTConnect in the box of the joint limits, path simplified), used
// when the straight Cartesian move would leave the joint limits, pass a
// singularity, or hit the table or the pedestal. Outcomes such as "no
// solution" and "timed out" are a status, not an exception (OMPL's style).

#include <functional>
#include <string>
#include <vector>

#include "common/arm/puma560.h"

namespace ephor::arm {

enum class JointPathStatus { kFound, kNoSolution, kTimedOut, kInvalidStart, kInvalidGoal };

const char* to_string(JointPathStatus status);

struct JointPath {
  JointPathStatus status = JointPathStatus::kNoSolution;
  std::string reason;             // when not found
  std::vector<Joints> waypoints;  // start ... goal (rad) when found; straight segments between
  double planning_time_s = 0.0;
};

struct JointPlannerConfig {
  double time_budget_s = 0.5;
  // Collision checks along an edge every this fraction of the joint box's diagonal.
  double check_resolution = 0.004;
  unsigned int seed = 560;  // OMPL's global seed, set once per process
};

class JointSpacePlanner {
 public:
  using ValidityFn = std::function<bool(const Joints&)>;

  JointSpacePlanner(const JointLimits& limits, JointPlannerConfig config = {});

  // A path from start to goal through states where `valid` is true. Thread
  // safe as long as `valid` is.
  JointPath plan(const Joints& start, const Joints& goal, const ValidityFn& valid) const;

 private:
  JointLimits limits_;
  JointPlannerConfig config_;
};

}  // namespace ephor::arm
