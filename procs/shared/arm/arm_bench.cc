// ephor-bench-arm: cost of the arm's computations on this machine (a
// benchmark, not a test): closed-form IK, the nearest solution, a straight
// Cartesian motion with the speed check, and an OMPL joint-space fallback.
//
//   tools/ephor bench arm [--benchmark_format=json]

#include <random>

#include <benchmark/benchmark.h>

#include "common/arm/arm_workcell.h"
#include "common/motion/motion_planner.h"

namespace {

using namespace ephor;

void BM_InverseAllSolutions(benchmark::State& state) {
  const geometry::Workcell cell;
  const arm::Puma560 puma = arm::make_puma(cell);
  const Eigen::Isometry3d pose = arm::tool_down_pose(cell, 1000.0, 200.0, 30.0, 0.4);
  for (auto _ : state) benchmark::DoNotOptimize(puma.inverse(pose));
}
BENCHMARK(BM_InverseAllSolutions);

void BM_NearestInverse(benchmark::State& state) {
  const geometry::Workcell cell;
  const arm::Puma560 puma = arm::make_puma(cell);
  const Eigen::Isometry3d pose = arm::tool_down_pose(cell, 1000.0, 200.0, 30.0, 0.4);
  const arm::Joints current = arm::park_joints(cell);
  for (auto _ : state) benchmark::DoNotOptimize(puma.nearest_inverse(pose, current));
}
BENCHMARK(BM_NearestInverse);

void BM_PlanCartesian600mm(benchmark::State& state) {
  const geometry::Workcell cell;
  const arm::MotionPlanner planner(cell);
  const arm::Joints start = *planner.arm().nearest_inverse(
      arm::tool_down_pose(cell, 1000.0, 150.0, 200.0, 0.0), arm::reference_joints());
  const Eigen::Isometry3d goal = arm::tool_down_pose(cell, 1000.0, 750.0, 200.0, 0.5);
  double duration = 0.0;
  for (auto _ : state) {
    const arm::MotionPlan plan = planner.plan(start, goal, 300.0);
    if (!plan.ok || plan.kind != arm::MotionKind::kCartesian)
      state.SkipWithError("not a Cartesian plan");
    duration = plan.trajectory.duration_s();
  }
  state.counters["motion_s"] = duration;
}
BENCHMARK(BM_PlanCartesian600mm)->Unit(benchmark::kMillisecond);

void BM_PlanAcrossTheColumnWithOmpl(benchmark::State& state) {
  const geometry::Workcell cell;
  const arm::MotionPlanner planner(cell);
  const arm::Joints start = *planner.arm().nearest_inverse(
      arm::tool_down_pose(cell, 150.0, 457.0, 200.0, 0.0), arm::reference_joints());
  const Eigen::Isometry3d goal = arm::tool_down_pose(cell, 1069.0, 457.0, 200.0, 0.0);
  double duration = 0.0, planning = 0.0;
  for (auto _ : state) {
    const arm::MotionPlan plan = planner.plan(start, goal, 300.0);
    if (!plan.ok || plan.kind != arm::MotionKind::kJointSpace)
      state.SkipWithError("no joint-space plan");
    duration = plan.trajectory.duration_s();
    planning = plan.joint_path.planning_time_s;
  }
  state.counters["motion_s"] = duration;
  state.counters["ompl_s"] = planning;
}
BENCHMARK(BM_PlanAcrossTheColumnWithOmpl)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
