// PlannerTask (planner_task.h): the planner's handlers and plan task on
// message streams that its fuzz target (rambo_planner) found faults with.
#include "procs/rambo/planner/planner_task.h"

#include <string>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "common/rambo/rambo_cell.h"

namespace ephor::rambo {
namespace {

constexpr int64_t kT0 = 1'700'000'000'000'000;  // us

// The built-in target's slow tumble 900 mm out, fitted at ref_utime.
rambo_prediction_t prediction(const RamboCell& cell, int64_t ref_utime) {
  rambo_prediction_t p{};
  p.fitted = true;
  p.model = "rigid-body";
  p.ref_utime = ref_utime;
  p.samples = 10;
  const TumblingMotion tm = cell.draw_motion(3, 10.0, 5.0);
  const Eigen::Quaterniond q(tm.pose0.linear());
  for (int i = 0; i < 3; ++i) {
    p.position_mm[i] = tm.pose0.translation()[i];
    p.velocity_mm_s[i] = tm.velocity_mm_s[i];
    p.body_rates_rad_s[i] = tm.body_rates_rad_s[i];
    p.principal_moments[i] = cell.principal_moments[i];
  }
  p.orientation_wxyz[0] = q.w();
  p.orientation_wxyz[1] = q.x();
  p.orientation_wxyz[2] = q.y();
  p.orientation_wxyz[3] = q.z();
  return p;
}

arm_state_t arm_at_start(const RamboCell& cell, int64_t utime) {
  arm_state_t s{};
  s.utime = utime;
  for (int j = 0; j < 6; ++j) s.q[j] = cell.start_joints[j];
  return s;
}

// The fuzz target's find: a prediction stamped 1700 years ahead passed the
// age check (its age negative) and the planner planned from it, integrating
// the tumble back across the span (1e13 RK4 steps: an int overflow). It is
// not planned from now; one stamped now is.
TEST(PlannerTask, APredictionStampedInTheFutureIsNotPlannedFrom) {
  const RamboCell cell = RamboCell::make(4);
  PlannerTask task(cell, PlannerTaskOptions{}, kT0);
  std::string why;
  ASSERT_TRUE(task.on_prediction(prediction(cell, 54'335'820'644'892'672), &why)) << why;
  task.on_arm_state(arm_at_start(cell, kT0));
  const auto clock = [] { return kT0 + 200'000; };
  PlannerTask::Period p = task.period(clock);
  EXPECT_EQ(p.plan.status, "prediction stamped in the future (clocks apart?)");
  EXPECT_EQ(p.plan.current_task, -1);
  EXPECT_FALSE(p.goal.has_value());

  ASSERT_TRUE(task.on_prediction(prediction(cell, kT0), &why)) << why;
  p = task.period(clock);
  EXPECT_NE(p.plan.status.find("diode"), std::string::npos) << p.plan.status;
  EXPECT_GE(p.plan.current_task, 0);
}

}  // namespace
}  // namespace ephor::rambo
