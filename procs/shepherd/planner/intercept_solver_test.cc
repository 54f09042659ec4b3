#include "procs/shepherd/planner/intercept_solver.h"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

namespace ephor::planner {
namespace {

constexpr double kCx = 609.5;
constexpr double kCy = 457.0;

// Hand-checked: 300-400-500 triangle, 500 mm at 300 mm/s after 0.5 s delay.
TEST(InterceptSolverTest, StationarySheepIsMetAfterTravelPlusDelay) {
  const auto t = InterceptSolver::earliest_time(0, 0, 300, 400, 0, 0, 300.0, 0.5);
  ASSERT_TRUE(t.has_value());
  EXPECT_NEAR(*t, 0.5 + 500.0 / 300.0, 1e-9);
}

TEST(InterceptSolverTest, ZeroVelocitySheepUnderTheToolIsMetWhenTheDelayEnds) {
  const auto t = InterceptSolver::earliest_time(100, 100, 100, 100, 0, 0, 300.0, 0.7);
  ASSERT_TRUE(t.has_value());
  EXPECT_NEAR(*t, 0.7, 1e-12);
  // Zero velocity has no heading: no lead is applied and the tool faces the centre.
  ArmModel arm;
  arm.x_mm = 0;
  arm.y_mm = 0;
  const Sheep sheep{1, 300, 400, 0, 0, SheepState::kVisible};
  const auto ic = InterceptSolver::solve(arm, sheep, 80.0, 0.5, kCx, kCy);
  ASSERT_TRUE(ic.has_value());
  EXPECT_DOUBLE_EQ(ic->x_mm, 300.0);
  EXPECT_DOUBLE_EQ(ic->y_mm, 400.0);
  EXPECT_NEAR(ic->theta_rad, std::atan2(kCy - 400.0, kCx - 300.0), 1e-12);
}

// Sheep 100 mm ahead moving away at 100 mm/s: 100 + 100 t = 300 t -> t = 0.5;
// with a 1 s delay: 100 + 100 t = 300 (t - 1) -> t = 2, met at x = 300.
TEST(InterceptSolverTest, SheepMovingAwayIsCaughtLater) {
  auto t = InterceptSolver::earliest_time(0, 0, 100, 0, 100, 0, 300.0, 0.0);
  ASSERT_TRUE(t.has_value());
  EXPECT_NEAR(*t, 0.5, 1e-9);
  t = InterceptSolver::earliest_time(0, 0, 100, 0, 100, 0, 300.0, 1.0);
  ASSERT_TRUE(t.has_value());
  EXPECT_NEAR(*t, 2.0, 1e-9);
}

// 400 - 100 t = 300 t -> t = 1.
TEST(InterceptSolverTest, SheepComingTowardsTheArm) {
  const auto t = InterceptSolver::earliest_time(0, 0, 400, 0, -100, 0, 300.0, 0.0);
  ASSERT_TRUE(t.has_value());
  EXPECT_NEAR(*t, 1.0, 1e-9);
}

// |(300, 100 t)| = 300 t -> t^2 = 90000 / 80000.
TEST(InterceptSolverTest, SheepCrossingTheArmsLine) {
  const auto t = InterceptSolver::earliest_time(0, 0, 300, 0, 0, 100, 300.0, 0.0);
  ASSERT_TRUE(t.has_value());
  EXPECT_NEAR(*t, std::sqrt(90000.0 / 80000.0), 1e-9);
}

TEST(InterceptSolverTest, SheepTooFastToCatchHasNoSolution) {
  EXPECT_FALSE(InterceptSolver::earliest_time(0, 0, 100, 0, 400, 0, 300.0, 0.0).has_value());
  // Exactly as fast as the arm and moving away: never caught.
  EXPECT_FALSE(InterceptSolver::earliest_time(0, 0, 100, 0, 300, 0, 300.0, 0.0).has_value());
  // As fast as the arm but coming closer: 300 - 300 t = 300 t -> t = 0.5.
  const auto t = InterceptSolver::earliest_time(0, 0, 300, 0, -300, 0, 300.0, 0.0);
  ASSERT_TRUE(t.has_value());
  EXPECT_NEAR(*t, 0.5, 1e-9);
}

// A faster sheep coming head-on is met on the way in: 1000 - 400 t = 300 t.
TEST(InterceptSolverTest, FasterSheepHeadOnIsMetBeforeItPasses) {
  const auto t = InterceptSolver::earliest_time(0, 0, 1000, 0, -400, 0, 300.0, 0.0);
  ASSERT_TRUE(t.has_value());
  EXPECT_NEAR(*t, 1000.0 / 700.0, 1e-9);
}

TEST(InterceptSolverTest, BadInputHasNoSolution) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(InterceptSolver::earliest_time(nan, 0, 1, 0, 0, 0, 300.0, 0.0).has_value());
  EXPECT_FALSE(InterceptSolver::earliest_time(0, 0, 1, 0, 0, 0, 0.0, 0.0).has_value());
  EXPECT_FALSE(InterceptSolver::earliest_time(0, 0, 1, 0, 0, 0, 300.0, -1.0).has_value());
}

// Lead 80 mm: the point to meet starts at x = 180 and moves at 100 mm/s:
// 180 + 100 t = 300 t -> t = 0.9; tool at 270, the sheep's centre at 190.
TEST(InterceptSolverTest, ToolIsPlacedAheadOfTheSheepAlongItsPath) {
  ArmModel arm;
  arm.x_mm = 0;
  arm.y_mm = 0;
  arm.speed_mm_s = 300;
  const Sheep sheep{1, 100, 0, 100, 0, SheepState::kVisible};
  const auto ic = InterceptSolver::solve(arm, sheep, 80.0, 0.0, kCx, kCy);
  ASSERT_TRUE(ic.has_value());
  EXPECT_NEAR(ic->t_s, 0.9, 1e-9);
  EXPECT_NEAR(ic->x_mm, 270.0, 1e-9);
  EXPECT_NEAR(ic->y_mm, 0.0, 1e-9);
  EXPECT_NEAR(ic->sheep_x_mm, 190.0, 1e-9);
  EXPECT_NEAR(ic->theta_rad, std::atan2(kCy, kCx - 270.0), 1e-12);
  // The arm really gets there in time: distance / speed == t.
  EXPECT_NEAR(std::hypot(ic->x_mm, ic->y_mm) / arm.speed_mm_s, ic->t_s, 1e-9);
}

}  // namespace
}  // namespace ephor::planner
