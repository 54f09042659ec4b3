#include "procs/shepherd/planner/lookahead_planner.h"

#include <gtest/gtest.h>

#include "procs/shepherd/planner/kinematic_field.h"

namespace ephor::planner {
namespace {

Sheep sheep(int id, double x, double y, double vx, double vy) {
  return Sheep{id, x, y, vx, vy, SheepState::kVisible};
}

// Greedy's mistake: A (right, leaves in 8.0 s) is more urgent than B (left,
// leaves in 9.2 s), but the arm sits next to B. A first: by the time the
// arm is back on the left, B is gone. B first: both are saved.
const Sheep kA = sheep(1, 929, 300, 36, 0);
const Sheep kB = sheep(2, 330, 300, -36, 0);
constexpr double kArmX = 150;
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

Scene crowded_rim() {
  Scene s;
  s.arm.x_mm = 600;
  s.arm.y_mm = 150;
  for (int i = 0; i < 10; ++i) {
    // Ten sheep near the long edges, each walking outwards.
    const double x = 150.0 + 100.0 * i;
    s.sheep.push_back(sheep(i + 1, x, i % 2 ? 750 : 160, 0, i % 2 ? 30.0 : -30.0));
  }
  return s;
}

PlannerConfig deep_search() {
  PlannerConfig config;
  config.lookahead_depth = 8;
  config.lookahead_max_candidates = 10;  // 10! / 2! orderings: far more than the budget allows
  config.lookahead_budget_s = 0.005;
  return config;
}

// Deterministic: a fake monotonic clock that advances 10 us per reading.
TEST(LookaheadPlannerTest, StopsAtTheBudgetAndReturnsItsBestSoFar) {
  int64_t fake_ns = 0;
  LookaheadPlanner planner{deep_search(), [&fake_ns] { return fake_ns += 10'000; }};
  const auto goal = planner.plan(crowded_rim());
  ASSERT_TRUE(goal.has_value());
  const LookaheadStats& st = planner.last_stats();
  EXPECT_FALSE(st.exhausted);
  // One clock reading per ordering: 5 ms / 10 us.
  EXPECT_EQ(st.orderings_scored, 500);
  EXPECT_LE(st.elapsed_s, 0.005 + 2e-5);
  EXPECT_EQ(st.best.size(), 8u);
  EXPECT_FALSE(st.greedy_score.better_than(st.best_score));  // never worse than greedy
}

// The real clock is wired in: the search stops on it, unfinished. How close
// to the budget it returns is a figure for a benchmark, not a test (68 ms for
// the 5 ms budget under the sanitizers on a loaded machine); the bound here
// only says it did not run on unbounded.
TEST(LookaheadPlannerTest, StopsOnTheRealClock) {
  LookaheadPlanner planner{deep_search()};
  ASSERT_TRUE(planner.plan(crowded_rim()).has_value());
  EXPECT_FALSE(planner.last_stats().exhausted);
  EXPECT_GT(planner.last_stats().orderings_scored, 1);
  EXPECT_LT(planner.last_stats().elapsed_s, 1.0);
}

}  // namespace
}  // namespace ephor::planner
