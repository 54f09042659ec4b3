// PlanTask, the stripe planner's plan task, with a plan of two stripes made
// up here and its answers recorded (main.cc sends them on the bus).
#include "procs/stripe/planner/plan_task.h"

#include <vector>

#include <gtest/gtest.h>

namespace ephor::stripe {
namespace {

struct Recorded : PlanOutputs {
  std::vector<GoalAction> goals;
  std::vector<CaptureAction> captures;
  std::vector<stripe_scan_t> scans;
  void goal(const GoalAction& a, arm_goal_t) override { goals.push_back(a); }
  void capture(const CaptureAction& a, stripe_capture_t) override { captures.push_back(a); }
  void scan(stripe_scan_t m) override { scans.push_back(m); }
};

PlanTaskConfig two_stripes(int* plans_made) {
  PlanTaskConfig c;
  c.plan = [plans_made](const arm::Joints& from) {
    ++*plans_made;
    RasterPlan p;
    p.goals = {from, from + arm::Joints::Constant(0.01)};
    return p;
  };
  c.wall_us = [] { return int64_t{1'700'000'000'000'000}; };
  return c;
}

TEST(PlanTask, WaitsForTheArmThenPlansFromWhereItIsAndAsksForTheProbe) {
  int plans = 0;
  Recorded out;
  PlanTask task(two_stripes(&plans), out, 1000);
  task.run(0.0, {}, std::nullopt, false);
  EXPECT_EQ(plans, 0) << "planned before the arm reported";
  EXPECT_TRUE(out.scans.empty());
  EXPECT_EQ(task.sequencer(), nullptr);

  const arm::Joints q = arm::Joints::Constant(0.2);
  task.run(0.1, {}, q, false);
  EXPECT_EQ(plans, 1);
  ASSERT_NE(task.sequencer(), nullptr);
  EXPECT_EQ(task.plan().goals.front(), q) << "the raster starts from the arm's joints";
  ASSERT_FALSE(out.scans.empty());
  EXPECT_EQ(out.scans.back().stripes_planned, 2);
  ASSERT_EQ(out.captures.size(), 1u);
  EXPECT_EQ(out.captures[0].stripe, -1) << "the probe comes first";
  EXPECT_GE(out.captures[0].request_id, 1000) << "ids count up from the start's";
  EXPECT_FALSE(task.finished());
}

TEST(PlanTask, AScanThatCannotBePlannedEndsTheTaskWithExitOneAndMovesNothing) {
  Recorded out;
  PlanTaskConfig c;
  c.plan = [](const arm::Joints&) -> RasterPlan {
    throw PlanError("region corner (x0, y0) = (-900, -900) mm is out of reach");
  };
  c.wall_us = [] { return int64_t{1}; };
  PlanTask task(std::move(c), out, 1);
  task.run(0.0, {}, arm::Joints::Zero(), false);
  EXPECT_TRUE(task.finished());
  EXPECT_EQ(task.exit_code(), 1);
  EXPECT_TRUE(out.goals.empty());
  EXPECT_TRUE(out.captures.empty());
  task.run(1.0, {}, arm::Joints::Zero(), false);
  EXPECT_TRUE(out.goals.empty()) << "a finished task stays still";
}

}  // namespace
}  // namespace ephor::stripe
