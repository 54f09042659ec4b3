#include "common/motion/joint_space_planner.h"

#include <chrono>
#include <memory>
#include <mutex>

#include <ompl/base/spaces/RealVectorStateSpace.h>
#include <ompl/geometric/SimpleSetup.h>
#include <ompl/geometric/planners/rrt/RRTConnect.h>
#include <ompl/util/Console.h>
#include <ompl/util/RandomNumbers.h>

namespace ephor::arm {

namespace ob = ompl::base;
namespace og = ompl::geometric;

const char* to_string(JointPathStatus status) {
  switch (status) {
    case JointPathStatus::kFound:
      return "found";
    case JointPathStatus::kNoSolution:
      return "no solution";
    case JointPathStatus::kTimedOut:
      return "timed out";
    case JointPathStatus::kInvalidStart:
      return "invalid start";
    case JointPathStatus::kInvalidGoal:
      return "invalid goal";
  }
  return "unknown";
}

JointSpacePlanner::JointSpacePlanner(const JointLimits& limits, JointPlannerConfig config)
    : limits_(limits), config_(config) {
  static std::once_flag once;
  const unsigned int seed = config_.seed;
  std::call_once(once, [seed] {
    // OMPL's seed is global and may only be set before its first RNG exists.
    ompl::msg::setLogLevel(ompl::msg::LOG_WARN);
    ompl::RNG::setSeed(seed);
  });
}

JointPath JointSpacePlanner::plan(const Joints& start, const Joints& goal,
                                  const ValidityFn& valid) const {
  JointPath out;
  if (!limits_.within(start) || !valid(start)) {
    out.status = JointPathStatus::kInvalidStart;
    out.reason = "start joints are outside the limits or in collision";
    return out;
  }
  if (!limits_.within(goal) || !valid(goal)) {
    out.status = JointPathStatus::kInvalidGoal;
    out.reason = "goal joints are outside the limits or in collision";
    return out;
  }
  auto space = std::make_shared<ob::RealVectorStateSpace>(6);
  ob::RealVectorBounds bounds(6);
  for (int i = 0; i < 6; ++i) {
    bounds.setLow(static_cast<unsigned>(i), limits_.q_min[i]);
    bounds.setHigh(static_cast<unsigned>(i), limits_.q_max[i]);
  }
  space->setBounds(bounds);
  og::SimpleSetup setup(space);
  auto to_joints = [](const ob::State* s) {
    const auto* rv = s->as<ob::RealVectorStateSpace::StateType>();
    Joints q;
    for (int i = 0; i < 6; ++i) q[i] = rv->values[i];
    return q;
  };
  setup.setStateValidityChecker(
      [&valid, &to_joints](const ob::State* s) { return valid(to_joints(s)); });
  setup.getSpaceInformation()->setStateValidityCheckingResolution(config_.check_resolution);
  ob::ScopedState<ob::RealVectorStateSpace> s(space), g(space);
  for (int i = 0; i < 6; ++i) {
    s[static_cast<unsigned>(i)] = start[i];
    g[static_cast<unsigned>(i)] = goal[i];
  }
  setup.setStartAndGoalStates(s, g);
  setup.setPlanner(std::make_shared<og::RRTConnect>(setup.getSpaceInformation()));
  setup.setup();

  const auto t0 = std::chrono::steady_clock::now();
  const ob::PlannerStatus status = setup.solve(config_.time_budget_s);
  out.planning_time_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (status == ob::PlannerStatus::EXACT_SOLUTION) {
    setup.simplifySolution(std::max(0.05, config_.time_budget_s * 0.2));
    const og::PathGeometric& path = setup.getSolutionPath();
    for (std::size_t i = 0; i < path.getStateCount(); ++i)
      out.waypoints.push_back(to_joints(path.getState(i)));
    out.status = JointPathStatus::kFound;
    return out;
  }
  if (status == ob::PlannerStatus::TIMEOUT || status == ob::PlannerStatus::APPROXIMATE_SOLUTION) {
    out.status = JointPathStatus::kTimedOut;
    out.reason = "joint-space planner found no collision-free path within " +
                 std::to_string(config_.time_budget_s) + " s";
  } else {
    out.status = JointPathStatus::kNoSolution;
    out.reason = std::string("joint-space planner: ") + status.asString();
  }
  return out;
}

}  // namespace ephor::arm
