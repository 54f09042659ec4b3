#include "procs/shepherd/planner/puma_arm_motion.h"

#include <cmath>

#include <gtest/gtest.h>

#include "procs/shepherd/planner/arm_configuration.h"
#include "procs/shepherd/planner/planner.h"

namespace ephor::planner {
namespace {

// Runs the arm until its motion ends; returns the time taken, s.
double run_to_end(PumaArmMotion& arm, double limit_s = 60.0) {
  double t = 0.0;
  while (!arm.step(0.01) && t < limit_s) t += 0.01;
  return t;
}

TEST(PumaArmMotionTest, AShortElevationMoveIsAStraightLineEndingAtTheGoal) {
  const geometry::Workcell cell;
  PumaArmMotion arm(cell);
  const auto parked = arm.tool_mm();
  EXPECT_NEAR(parked[0], cell.field_length_mm - 60.0, 1.0);
  EXPECT_NEAR(parked[2], cell.elevation_plane_z_mm, 1.0);
  ASSERT_TRUE(arm.start(parked[0] - 200.0, parked[1] + 100.0, cell.elevation_plane_z_mm, 0.0));
  const double t = run_to_end(arm);
  const auto at = arm.tool_mm();
  EXPECT_NEAR(at[0], parked[0] - 200.0, 1.0);
  EXPECT_NEAR(at[1], parked[1] + 100.0, 1.0);
  // 224 mm at 300 mm/s with acceleration: between 0.75 s and 3 s.
  EXPECT_GT(t, 0.74);
  EXPECT_LT(t, 3.0);
  EXPECT_EQ(arm.moves(), 1);
  EXPECT_EQ(arm.joint_space_moves(), 0);
  EXPECT_NEAR(arm.move_time_s(), t, 0.05) << "the bench's arm time is the trajectory's";
}

TEST(PumaArmMotionTest, AConfigurationChangeTakesTheArmSeconds) {
  const geometry::Workcell cell;
  PumaArmMotion arm(cell);
  const ArmConfiguration configuration(cell);
  // Find a point of the field's edge band the parked arm cannot reach as it is.
  double gx = -1.0, gy = -1.0;
  for (double y = 100.0; y < cell.field_width_mm && gx < 0.0; y += 50.0) {
    if (configuration.needs_switch(arm.joints(), 100.0, y, cell.elevation_plane_z_mm, 0.0)) {
      gx = 100.0;
      gy = y;
    }
  }
  ASSERT_GE(gx, 0.0) << "no point on the left edge needs a configuration change";
  ASSERT_TRUE(arm.start(gx, gy, cell.elevation_plane_z_mm, 0.0));
  const double t = run_to_end(arm);
  EXPECT_EQ(arm.joint_space_moves(), 1);
  EXPECT_GT(t, 8.0) << "a configuration change swings the arm over the top";
  EXPECT_NEAR(arm.joint_space_time_s(), t, 0.05);
  EXPECT_NEAR(arm.move_time_s(), t, 0.05);
  EXPECT_NEAR(arm.tool_mm()[0], gx, 1.0);
  EXPECT_NEAR(arm.tool_mm()[1], gy, 1.0);
}

TEST(PumaArmMotionTest, TheMultiPlannerWithThePumaKeepsOneSheepOnTheFieldForTenMinutes) {
  KinematicFieldConfig fc;
  fc.sheep = 1;
  fc.seed = 7;
  fc.velocity_lag_s = 0.15;
  fc.hide_radius_mm = 150.0;
  auto arm = std::make_shared<PumaArmMotion>(fc.workcell);
  fc.arm_motion = arm;
  KinematicField field(fc);
  auto planner = make_planner("multi", PlannerConfig{});
  for (int i = 0; i < 600 * 30; ++i) {  // 10 simulated minutes
    field.step(1.0 / 30.0);
    for (const auto& [id, ok] : field.take_done()) planner->on_motion_done(id, ok);
    const Scene scene = field.scene(ArmModel{});
    ASSERT_TRUE(scene.arm.joints_known);
    if (const auto goal = planner->plan(scene)) field.send(*goal);
  }
  EXPECT_EQ(field.escapes(), 0);
  EXPECT_GE(field.touches(), 1);
  EXPECT_GE(arm->moves(), 3);
}

}  // namespace
}  // namespace ephor::planner
