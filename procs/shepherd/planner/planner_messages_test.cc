#include "procs/shepherd/planner/planner_messages.h"

#include <cmath>
#include <cstdint>
#include <limits>

#include <gtest/gtest.h>

#include "common/calibration/field_calibration.h"

namespace ephor::planner {
namespace {

constexpr int64_t kOffset = 1'700'000'000'000'000;  // a run's start, wall clock us

TEST(PlannerMessagesTest, GoalIdsGoOutOffsetAndComeBack) {
  const auto calibration = calibration::FieldCalibration::from_camera({}, {});
  Goal goal;
  goal.goal_id = 7;
  goal.plane = Plane::kObject;
  goal.x_mm = 400.0;
  goal.y_mm = 300.0;
  goal.target = 3;
  const arm_goal_t m = goal_message_of(goal, calibration, kOffset, 42);
  EXPECT_EQ(m.goal_id, kOffset + 7);
  EXPECT_EQ(m.plane, int8_t{arm_goal_t::PLANE_OBJECT});  // a copy: no ODR-use
  EXPECT_EQ(m.source_frame_utime, 42);
  EXPECT_EQ(m.target_object, 3);
  const Eigen::Vector2d p = calibration.field_to_image(400.0, 300.0, calibration::Plane::kObject);
  EXPECT_NEAR(m.u, p.x(), 1e-3);
  EXPECT_NEAR(m.v, p.y(), 1e-3);
  EXPECT_EQ(planner_goal_id(m.goal_id, kOffset), 7);
}

// Found by the fuzz target shepherd_planner: a MOTION_DONE naming goal
// INT64_MIN overflowed goal_id - offset (undefined behaviour). It names no
// goal of the planner's.
TEST(PlannerMessagesTest, AGoalIdFarBelowTheOffsetIsNoGoalOfOurs) {
  constexpr int64_t kMin = std::numeric_limits<int64_t>::min();
  constexpr int64_t kMax = std::numeric_limits<int64_t>::max();
  EXPECT_EQ(planner_goal_id(kMin, kOffset), -1);
  EXPECT_EQ(planner_goal_id(kMin + kOffset - 1, kOffset), -1);
  EXPECT_EQ(planner_goal_id(kMin + kOffset, kOffset), kMin);
  EXPECT_EQ(planner_goal_id(kMax, kOffset), kMax - kOffset);
  EXPECT_EQ(planner_goal_id(kMax, -1), -1);
  EXPECT_EQ(planner_goal_id(5, 0), 5);
}

}  // namespace
}  // namespace ephor::planner
