#include "procs/shepherd/planner/single_sheep_planner.h"

#include <cmath>

#include <gtest/gtest.h>

#include "procs/shepherd/planner/kinematic_field.h"

namespace ephor::planner {
namespace {

Scene make_scene(std::vector<Sheep> all, double arm_x, double arm_y, double now, bool lowered) {
  Scene s;
  s.now_s = now;
  s.sheep = std::move(all);
  s.arm.x_mm = arm_x;
  s.arm.y_mm = arm_y;
  s.arm.lowered = lowered;
  return s;
}

// The paper's single-sheep version: wait at the field boundary, lowered,
// turn the sheep, raise, park in the lower-right corner.
TEST(SingleSheepPlannerTest, WaitsAtTheBoundaryTurnsTheSheepThenParks) {
  const PlannerConfig config;
  SingleSheepPlanner planner{config};
  const Sheep a{1, 600, 700, -30, 0, SheepState::kVisible};
  const auto move = planner.plan(make_scene({a}, 1000, 200, 0.0, false));
  ASSERT_TRUE(move.has_value());
  EXPECT_EQ(move->plane, Plane::kElevation);
  EXPECT_NEAR(move->x_mm, config.field_margin_mm, 1e-9);  // on the left boundary
  EXPECT_NEAR(move->y_mm, 700.0, 1e-9);
  ASSERT_TRUE(planner.on_motion_done(move->goal_id, true));
  Sheep later = a;
  later.x_mm -= 30.0 * 4.0;
  const auto lower = planner.plan(make_scene({later}, move->x_mm, move->y_mm, 4.0, false));
  ASSERT_TRUE(lower.has_value());
  EXPECT_EQ(lower->plane, Plane::kObject);
  ASSERT_TRUE(planner.on_motion_done(lower->goal_id, true));
  // The sheep drifts sideways: the lowered tool follows its path.
  Sheep drifting = later;
  drifting.x_mm -= 60.0;
  drifting.vy_mm_s = 3.0;
  drifting.vx_mm_s = -29.8;
  const auto correct = planner.plan(make_scene({drifting}, lower->x_mm, lower->y_mm, 6.0, true));
  ASSERT_TRUE(correct.has_value());
  EXPECT_EQ(correct->plane, Plane::kObject);
  EXPECT_GT(correct->y_mm, 720.0);
  ASSERT_TRUE(planner.on_motion_done(correct->goal_id, true));
  // Reoriented toward the centre by the touch.
  Sheep turned = drifting;
  const double to_cx = config.workcell.centre_x_mm() - turned.x_mm;
  const double to_cy = config.workcell.centre_y_mm() - turned.y_mm;
  turned.vx_mm_s = 30.0 * to_cx / std::hypot(to_cx, to_cy);
  turned.vy_mm_s = 30.0 * to_cy / std::hypot(to_cx, to_cy);
  const auto raise = planner.plan(make_scene({turned}, correct->x_mm, correct->y_mm, 12.0, true));
  ASSERT_TRUE(raise.has_value());
  EXPECT_EQ(raise->plane, Plane::kElevation);
  ASSERT_TRUE(planner.on_motion_done(raise->goal_id, true));
  const auto park = planner.plan(make_scene({turned}, raise->x_mm, raise->y_mm, 13.0, false));
  ASSERT_TRUE(park.has_value());
  EXPECT_EQ(planner.status().phase, "parking");
  EXPECT_EQ(park->target, -1);
  // The first leg heads for the lower-right corner.
  const double to_park = std::atan2(config.park_y_mm - raise->y_mm, config.park_x_mm - raise->x_mm);
  EXPECT_NEAR(std::atan2(park->y_mm - raise->y_mm, park->x_mm - raise->x_mm), to_park, 1e-9);
}

TEST(SingleSheepPlannerTest, KeepsOneSheepOnTheFieldInTheKinematicStandIn) {
  KinematicFieldConfig fc;
  fc.sheep = 1;
  fc.seed = 3;
  KinematicField field{fc};
  auto planner = make_planner("single", PlannerConfig{});
  const ArmModel arm;
  const double dt = 1.0 / 30.0;
  for (int i = 0; i < static_cast<int>(180.0 / dt); ++i) {
    field.step(dt);
    for (const auto& [id, ok] : field.take_done()) planner->on_motion_done(id, ok);
    if (auto goal = planner->plan(field.scene(arm))) field.send(*goal);
  }
  EXPECT_EQ(field.escapes(), 0);
  EXPECT_GT(field.touches(), 0);
}

}  // namespace
}  // namespace ephor::planner
