#include "procs/planner/lookahead_planner.h"

#include <gtest/gtest.h>

#include "procs/planner/kinematic_field.h"

namespace ephor::planner {
namespace {

Sheep sheep(int id, double x, double y, double vx, double vy) {
  return Sheep{id, x, y, vx, vy, SheepState::kVisible};
}

// Greedy's mistake: A (right, leaves in 11 s) is more urgent than B (left,
// leaves in 12 s), but the arm sits next to B. A first: by the time the arm
// is back on the left, B is gone. B first: both are saved.
const Sheep kA = sheep(1, 889, 300, 30, 0);
const Sheep kB = sheep(2, 360, 300, -30, 0);
constexpr double kArmX = 250;
constexpr double kArmY = 300;

int escapes_with(const std::string& kind, double seconds) {
  KinematicFieldConfig fc;
  fc.start_x_mm = kArmX;
  fc.start_y_mm = kArmY;
  fc.respawn_s = 1e9;  // count only these two sheep
  KinematicField field{fc, {kA, kB}};
  auto planner = make_planner(kind, PlannerConfig{});
  const ArmModel arm;
  const double dt = 1.0 / 30.0;
  for (int i = 0; i < static_cast<int>(seconds / dt); ++i) {
    field.step(dt);
    for (const auto& [id, ok] : field.take_done()) planner->on_motion_done(id, ok);
    if (auto goal = planner->plan(field.scene(arm))) field.send(*goal);
  }
  return field.escapes();
}

TEST(LookaheadPlannerTest, SavesTheNearSheepFirstWhereGreedyOrderLosesOne) {
  LookaheadPlanner planner{PlannerConfig{}};
  Scene s;
  s.sheep = {kA, kB};
  s.arm.x_mm = kArmX;
  s.arm.y_mm = kArmY;
  const auto goal = planner.plan(s);
  ASSERT_TRUE(goal.has_value());
  EXPECT_EQ(goal->target, 2);
  EXPECT_EQ(planner.last_stats().greedy_score.escapes, 1);
  EXPECT_EQ(planner.last_stats().best_score.escapes, 0);
  EXPECT_TRUE(planner.last_stats().exhausted);

  const int multi = escapes_with("multi", 30.0);
  const int lookahead = escapes_with("lookahead", 30.0);
  EXPECT_LE(lookahead, multi);
  EXPECT_EQ(lookahead, 0);
  EXPECT_EQ(multi, 1);
}

TEST(LookaheadPlannerTest, ReturnsItsBestSoFarWhenTheBudgetEnds) {
  PlannerConfig config;
  config.lookahead_depth = 8;
  config.lookahead_max_candidates = 10;  // 10! / 2! orderings: far more than 5 ms
  config.lookahead_budget_s = 0.005;
  LookaheadPlanner planner{config};
  Scene s;
  s.arm.x_mm = 600;
  s.arm.y_mm = 150;
  for (int i = 0; i < 10; ++i) {
    // Ten sheep around the rim, each walking outwards.
    const double x = 150.0 + 100.0 * i;
    s.sheep.push_back(sheep(i + 1, x, i % 2 ? 750 : 160, 0, i % 2 ? 30.0 : -30.0));
  }
  const auto goal = planner.plan(s);
  ASSERT_TRUE(goal.has_value());
  const LookaheadStats& st = planner.last_stats();
  EXPECT_FALSE(st.exhausted);
  EXPECT_GT(st.orderings_scored, 1);
  EXPECT_EQ(st.best.size(), 8u);
  // Anytime: stops at the budget (one ordering's scoring past it at most;
  // slack for a loaded 2-core machine).
  EXPECT_LT(st.elapsed_s, config.lookahead_budget_s + 0.010);
  EXPECT_FALSE(st.greedy_score.better_than(st.best_score));
}

}  // namespace
}  // namespace ephor::planner
