#include "procs/shepherd/planner/multi_sheep_planner.h"

#include <cmath>
#include <limits>
#include <optional>

#include <gtest/gtest.h>

namespace ephor::planner {
namespace {

constexpr double kCx = 609.5;
constexpr double kCy = 457.0;

Sheep sheep(int id, double x, double y, double vx, double vy) {
  return Sheep{id, x, y, vx, vy, SheepState::kVisible};
}

// A sheep at (x, y) walking at 30 mm/s straight toward the field centre.
Sheep to_centre(int id, double x, double y) {
  const double d = std::hypot(kCx - x, kCy - y);
  return sheep(id, x, y, 30.0 * (kCx - x) / d, 30.0 * (kCy - y) / d);
}

Scene make_scene(std::vector<Sheep> all, double arm_x = 600, double arm_y = 150, double now = 0) {
  Scene s;
  s.now_s = now;
  s.sheep = std::move(all);
  s.arm.x_mm = arm_x;
  s.arm.y_mm = arm_y;
  return s;
}

// Sheep A leaves over the left edge in 10 s; B over the right edge in 12.3 s.
const Sheep kA = sheep(1, 300, 600, -30, 0);
const Sheep kB = sheep(2, 850, 300, 30, 0);

TEST(MultiSheepPlannerTest, Step1PicksTheSheepLeavingSoonest) {
  MultiSheepPlanner planner{PlannerConfig{}};
  const auto goal = planner.plan(make_scene({kB, kA}));
  ASSERT_TRUE(goal.has_value());
  EXPECT_EQ(goal->target, 1);
  EXPECT_EQ(goal->plane, Plane::kElevation);
  EXPECT_EQ(planner.phase(), SaveCyclePlanner::Phase::kMoving);
  EXPECT_EQ(planner.status().num_candidates, 2);
  ASSERT_EQ(planner.last_verdicts().size(), 1u);
  EXPECT_EQ(planner.last_verdicts()[0].verdict, Verdict::kAccepted);
  // The goal is on A's path, ahead of it, inside the field, facing where the
  // touch will send A: toward the centre, past the pedestal.
  EXPECT_NEAR(goal->y_mm, 600.0, 1e-9);
  EXPECT_LT(goal->x_mm, 300.0);
  EXPECT_GT(goal->x_mm, 25.0);
  const FieldRules rules{PlannerConfig{}};
  EXPECT_NEAR(goal->theta_rad, rules.redirect_heading(goal->x_mm, goal->y_mm, {kB, kA}, 1), 1e-12);
  EXPECT_LE(std::abs(goal->theta_rad - std::atan2(kCy - goal->y_mm, kCx - goal->x_mm)),
            PlannerConfig{}.redirect_max_rad + 1e-12);
}

TEST(MultiSheepPlannerTest, Step1SkipsASheepAlreadyHeadingToTheCentre) {
  MultiSheepPlanner planner{PlannerConfig{}};
  const auto goal = planner.plan(make_scene({to_centre(1, 300, 600), kB}));
  ASSERT_TRUE(goal.has_value());
  EXPECT_EQ(goal->target, 2);
  EXPECT_EQ(planner.status().num_candidates, 1);
}

TEST(MultiSheepPlannerTest, Step2RejectsAnInterceptOutsideTheFieldAndTakesTheNextSheep) {
  MultiSheepPlanner planner{PlannerConfig{}};
  // 120 mm from the edge at 30 mm/s: leaves first, but the tool cannot be
  // down in front of it inside the field in time.
  const Sheep hopeless = sheep(3, 120, 600, -30, 0);
  const auto goal = planner.plan(make_scene({kB, hopeless}));
  ASSERT_TRUE(goal.has_value());
  EXPECT_EQ(goal->target, 2);
  ASSERT_EQ(planner.last_verdicts().size(), 2u);
  EXPECT_EQ(planner.last_verdicts()[0].sheep_id, 3);
  EXPECT_EQ(planner.last_verdicts()[0].verdict, Verdict::kOutsideField);
  EXPECT_EQ(planner.last_verdicts()[1].verdict, Verdict::kAccepted);
}

TEST(MultiSheepPlannerTest, Step2RejectsAnInterceptOnAnotherSheepsPath) {
  MultiSheepPlanner planner{PlannerConfig{}};
  Intercept ic;
  const Scene clear = make_scene({kA, kB});
  ASSERT_EQ(planner.judge(clear, kA, &ic).verdict, Verdict::kAccepted);
  // Sheep 3 walks up (+y) through A's intercept point exactly at the
  // intercept time; it leaves later than A and B.
  const Sheep crossing = sheep(3, ic.x_mm, ic.y_mm - 30.0 * ic.t_s, 0, 30);
  MultiSheepPlanner fresh{PlannerConfig{}};
  const auto goal = fresh.plan(make_scene({kA, kB, crossing}));
  ASSERT_TRUE(goal.has_value());
  EXPECT_EQ(goal->target, 2);
  ASSERT_GE(fresh.last_verdicts().size(), 2u);
  EXPECT_EQ(fresh.last_verdicts()[0].sheep_id, 1);
  EXPECT_EQ(fresh.last_verdicts()[0].verdict, Verdict::kOnOtherSheepPath);
  EXPECT_EQ(fresh.last_verdicts()[0].blocking_sheep, 3);
}

TEST(MultiSheepPlannerTest, ParksAtTheLowerRightCornerWhenNobodyNeedsSaving) {
  const PlannerConfig config;
  MultiSheepPlanner planner{config};
  const Sheep resting = sheep(3, 900, 700, 0, 0);
  const Sheep near_centre = sheep(4, kCx + 50, kCy, 30, 0);  // in the centre zone
  const std::vector<Sheep> calm{to_centre(1, 300, 600), to_centre(2, 1000, 200), resting,
                                near_centre};
  double x = 400;
  double y = 60;
  double now = 0.0;
  // The arm goes to the corner in legs of at most park_leg_mm.
  int legs = 0;
  for (; legs < 20; ++legs) {
    const auto goal = planner.plan(make_scene(calm, x, y, now));
    if (!goal) break;
    EXPECT_GE(
        std::hypot(goal->x_mm - config.workcell.base_x_mm, goal->y_mm - config.workcell.base_y_mm),
        config.tool_keepout_mm);
    EXPECT_EQ(goal->target, -1);
    EXPECT_EQ(goal->plane, Plane::kElevation);
    EXPECT_EQ(planner.status().phase, "parking");
    EXPECT_LE(std::hypot(goal->x_mm - x, goal->y_mm - y), config.park_leg_mm + 1e-9);
    ASSERT_TRUE(planner.on_motion_done(goal->goal_id, true));
    x = goal->x_mm;
    y = goal->y_mm;
    now += 0.6;
  }
  EXPECT_EQ(legs, 5);  // 759 mm from (400, 60) to (1159, 60); the last 9 mm are close enough
  EXPECT_LE(std::hypot(x - config.park_x_mm, y - config.park_y_mm), 15.0);
  EXPECT_GT(x, kCx);  // right
  EXPECT_LT(y, kCy);  // lower in the image (y up)
  EXPECT_EQ(planner.status().phase, "parked");
}

TEST(MultiSheepPlannerTest, ASheepNeedingSavingInterruptsTheWayToThePark) {
  MultiSheepPlanner planner{PlannerConfig{}};
  const auto leg = planner.plan(make_scene({to_centre(1, 300, 600)}, 100, 800));
  ASSERT_TRUE(leg.has_value());
  EXPECT_EQ(planner.status().phase, "parking");
  ASSERT_TRUE(planner.on_motion_done(leg->goal_id, true));
  const auto save = planner.plan(make_scene({kA}, leg->x_mm, leg->y_mm, 0.6));
  ASSERT_TRUE(save.has_value());
  EXPECT_EQ(save->target, 1);
}

TEST(MultiSheepPlannerTest, KeepsOneGoalOutstandingAndReplansAfterAFailedGoal) {
  MultiSheepPlanner planner{PlannerConfig{}};
  const auto g1 = planner.plan(make_scene({kA, kB}));
  ASSERT_TRUE(g1.has_value());
  // Re-evaluates, but sends nothing while the goal is out.
  EXPECT_FALSE(planner.plan(make_scene({kA, kB}, 600, 150, 0.1)).has_value());
  EXPECT_FALSE(planner.on_motion_done(g1->goal_id + 100, true));  // not ours
  EXPECT_TRUE(planner.on_motion_done(g1->goal_id, false));
  // The next goal after a short back-off (0.25 s from when the failure is seen).
  EXPECT_FALSE(planner.plan(make_scene({kA, kB}, 650, 200, 0.5)).has_value());
  const auto g2 = planner.plan(make_scene({kA, kB}, 650, 200, 0.8));
  ASSERT_TRUE(g2.has_value());
  EXPECT_GT(g2->goal_id, g1->goal_id);
  EXPECT_EQ(g2->plane, Plane::kElevation);
  EXPECT_EQ(g2->target, 1);
  EXPECT_EQ(planner.status().goals_failed, 1);
  // No motion_done at all: after the timeout the goal counts as failed.
  EXPECT_FALSE(planner.plan(make_scene({kA, kB}, 650, 200, 1.0)).has_value());
  EXPECT_FALSE(planner.plan(make_scene({kA, kB}, 650, 200, 60.0)).has_value());  // back-off 0.5 s
  const auto g3 = planner.plan(make_scene({kA, kB}, 650, 200, 60.6));
  ASSERT_TRUE(g3.has_value());
  EXPECT_GT(g3->goal_id, g2->goal_id);
  EXPECT_EQ(planner.status().goals_timed_out, 1);
  EXPECT_FALSE(planner.on_motion_done(g2->goal_id, true));  // late: ignored
}

// An arm that refuses everything is not flooded: the back-off doubles up to
// 2 s, and one success resets it.
TEST(MultiSheepPlannerTest, BacksOffFromAnArmThatKeepsFailing) {
  MultiSheepPlanner planner{PlannerConfig{}};
  std::vector<double> sent_at;
  double now = 0.0;
  for (int step = 0; step < 300 && sent_at.size() < 7; ++step, now += 0.05) {
    if (const auto g = planner.plan(make_scene({kA}, 600, 150, now))) {
      sent_at.push_back(now);
      planner.on_motion_done(g->goal_id, false);
    }
  }
  ASSERT_EQ(sent_at.size(), 7u);
  const double expected[] = {0.25, 0.5, 1.0, 2.0, 2.0, 2.0};
  for (size_t i = 0; i < 6; ++i) {
    // One planning period (0.05 s) of rounding: the failure is seen on the next job.
    EXPECT_NEAR(sent_at[i + 1] - sent_at[i], expected[i] + 0.05, 0.051) << "gap " << i;
  }
}

// Moves the scene on by dt: sheep in straight lines, the arm where told.
Scene advance(const std::vector<Sheep>& all, double dt, double arm_x, double arm_y, bool lowered,
              double now) {
  std::vector<Sheep> moved;
  for (Sheep s : all) {
    s.x_mm += s.vx_mm_s * dt;
    s.y_mm += s.vy_mm_s * dt;
    moved.push_back(s);
  }
  Scene sc = make_scene(moved, arm_x, arm_y, now);
  sc.arm.lowered = lowered;
  return sc;
}

// Takes `planner` through its first move for `target` and the lowering that
// follows (the arm arriving `early_mm` farther along -x than planned, at
// t = 2 s); both motions done. Returns the lowering goal, nullopt (with a
// test failure) if either did not come.
std::optional<Goal> move_and_lower(MultiSheepPlanner& planner, const Sheep& target,
                                   double early_mm = 0.0) {
  const auto move = planner.plan(make_scene({target}));
  if (!move || !planner.on_motion_done(move->goal_id, true)) {
    ADD_FAILURE() << "no first move";
    return std::nullopt;
  }
  const auto lower =
      planner.plan(advance({target}, 2.0, move->x_mm - early_mm, move->y_mm, false, 2.0));
  if (!lower || lower->plane != Plane::kObject || !planner.on_motion_done(lower->goal_id, true)) {
    ADD_FAILURE() << "no lowering after the move";
    return std::nullopt;
  }
  return lower;
}

TEST(MultiSheepPlannerTest, FullCycleMoveVerifyLowerTurnRaiseThenPark) {
  MultiSheepPlanner planner{PlannerConfig{}};
  const Scene s0 = make_scene({kA});
  const auto move = planner.plan(s0);
  ASSERT_TRUE(move.has_value());
  ASSERT_EQ(move->plane, Plane::kElevation);
  // The arm arrives as planned.
  const double t1 = std::hypot(move->x_mm - 600, move->y_mm - 150) / 300.0 + s0.arm.overhead_s;
  ASSERT_TRUE(planner.on_motion_done(move->goal_id, true));
  const auto lower = planner.plan(advance({kA}, t1, move->x_mm, move->y_mm, false, t1));
  ASSERT_TRUE(lower.has_value());
  EXPECT_EQ(lower->plane, Plane::kObject);
  EXPECT_EQ(lower->target, 1);
  EXPECT_NEAR(lower->x_mm, move->x_mm, 40.0);
  EXPECT_NEAR(lower->y_mm, 600.0, 1e-6);
  EXPECT_EQ(planner.status().phase, "lowering");
  // Down: wait for the touch.
  const double t2 = t1 + 1.0;
  ASSERT_TRUE(planner.on_motion_done(lower->goal_id, true));
  EXPECT_FALSE(planner.plan(advance({kA}, t2, lower->x_mm, lower->y_mm, true, t2)).has_value());
  EXPECT_EQ(planner.status().phase, "turning");
  // Touched: the sheep now walks toward the centre.
  Scene turned = advance({kA}, t2 + 0.1, lower->x_mm, lower->y_mm, true, t2 + 0.1);
  turned.sheep[0] = to_centre(1, turned.sheep[0].x_mm, turned.sheep[0].y_mm);
  const auto raise = planner.plan(turned);
  ASSERT_TRUE(raise.has_value());
  EXPECT_EQ(raise->plane, Plane::kElevation);
  EXPECT_DOUBLE_EQ(raise->x_mm, lower->x_mm);
  EXPECT_DOUBLE_EQ(raise->y_mm, lower->y_mm);
  EXPECT_EQ(planner.status().saves, 1);
  // Raised, nobody else to save: park.
  ASSERT_TRUE(planner.on_motion_done(raise->goal_id, true));
  Scene up = turned;
  up.now_s += 1.0;
  up.arm.lowered = false;
  const auto park = planner.plan(up);
  ASSERT_TRUE(park.has_value());
  EXPECT_EQ(park->target, -1);
  EXPECT_EQ(planner.status().phase, "parking");
  EXPECT_TRUE(move->goal_id < lower->goal_id && lower->goal_id < raise->goal_id &&
              raise->goal_id < park->goal_id);
}

// Issue 13: at the paper's 8 mm/s the lowered tool may wait 20 s for its
// sheep; a second sheep that would leave meanwhile makes it give up the wait
// (while the second is still savable), not after the second has gone.
TEST(MultiSheepPlannerTest, GivesUpAWaitThatWouldLoseAnotherSheep) {
  MultiSheepPlanner planner{PlannerConfig{}};
  const Sheep slow = sheep(1, 250, 700, -8, 0);  // leaves over the left edge in 31 s
  // The arm is early, 150 mm farther along the sheep's path: it lowers
  // there and the sheep walks under it, 20-odd seconds at 8 mm/s.
  const auto lower = move_and_lower(planner, slow, 150.0);
  ASSERT_TRUE(lower.has_value());
  // Down, the sheep still well short of the tool: a long wait, nobody else.
  EXPECT_FALSE(planner.plan(advance({slow}, 3.0, lower->x_mm, lower->y_mm, true, 3.0)));
  ASSERT_EQ(planner.status().phase, "turning");
  // A second sheep, 150 mm from the bottom edge, heading out at 8 mm/s:
  // it leaves in 19 s, the arm needs about 5 s to reach it.
  Scene two = advance({slow}, 4.0, lower->x_mm, lower->y_mm, true, 4.0);
  two.sheep.push_back(sheep(2, 700, 150, 0, -8));
  const auto raise = planner.plan(two);
  ASSERT_TRUE(raise.has_value()) << "kept waiting while sheep 2 walks off";
  EXPECT_EQ(raise->plane, Plane::kElevation);
  EXPECT_DOUBLE_EQ(raise->x_mm, lower->x_mm);
  EXPECT_EQ(planner.status().saves, 0);
}

// ...but a sheep that leaves later than the wait plus the arm's way to it
// does not interrupt the wait.
TEST(MultiSheepPlannerTest, KeepsWaitingWhenTheOtherSheepCanWait) {
  MultiSheepPlanner planner{PlannerConfig{}};
  const Sheep slow = sheep(1, 250, 700, -8, 0);
  const auto lower = move_and_lower(planner, slow, 150.0);
  ASSERT_TRUE(lower.has_value());
  EXPECT_FALSE(planner.plan(advance({slow}, 3.0, lower->x_mm, lower->y_mm, true, 3.0)));
  Scene two = advance({slow}, 4.0, lower->x_mm, lower->y_mm, true, 4.0);
  // 40 s from the right edge: more than the longest wait (30 s) plus the
  // arm's way to it.
  two.sheep.push_back(sheep(2, 900, 600, 8, 0));
  EXPECT_FALSE(planner.plan(two).has_value());
  EXPECT_EQ(planner.status().phase, "turning");
}

TEST(MultiSheepPlannerTest, Step3RecheckDoesNotLowerOntoAnotherSheep) {
  MultiSheepPlanner planner{PlannerConfig{}};
  const auto move = planner.plan(make_scene({kA}));
  ASSERT_TRUE(move.has_value());
  ASSERT_TRUE(planner.on_motion_done(move->goal_id, true));
  // During the move a resting sheep got pushed right under the arm.
  Scene there = advance({kA}, 2.0, move->x_mm, move->y_mm, false, 2.0);
  there.sheep.push_back(sheep(5, move->x_mm + 20, move->y_mm - 30, 0, 0));
  const auto next = planner.plan(there);
  EXPECT_TRUE(!next.has_value() || next->plane != Plane::kObject);
  EXPECT_NE(planner.status().phase, "lowering");
}

TEST(MultiSheepPlannerTest, ArmSlowerThanHopedMovesAgainInsteadOfLoweringBehindTheSheep) {
  MultiSheepPlanner planner{PlannerConfig{}};
  const Sheep far = sheep(1, 600, 850, -30, 0);  // 20 s from the left edge
  const auto move = planner.plan(make_scene({far}));
  ASSERT_TRUE(move.has_value());
  ASSERT_TRUE(planner.on_motion_done(move->goal_id, true));
  // The arm took 6 s longer than planned: the sheep's tail is nearly past
  // the point, lowering there would miss.
  const double planned = std::hypot(move->x_mm - 600, move->y_mm - 150) / 300.0;
  const double late = planned + 6.0;
  const auto next = planner.plan(advance({far}, late, move->x_mm, move->y_mm, false, late));
  ASSERT_TRUE(next.has_value());
  EXPECT_EQ(next->plane, Plane::kElevation);
  EXPECT_EQ(next->target, 1);
  EXPECT_LT(next->x_mm, move->x_mm - 40.0);  // further along A's path (-x)
}

TEST(MultiSheepPlannerTest, TargetGoneOrTurnedOnItsOwnDuringTheMoveMeansChoosingAgain) {
  {
    MultiSheepPlanner planner{PlannerConfig{}};
    const auto move = planner.plan(make_scene({kA, kB}));
    ASSERT_TRUE(move.has_value() && move->target == 1);
    ASSERT_TRUE(planner.on_motion_done(move->goal_id, true));
    const auto next = planner.plan(advance({kB}, 2.0, move->x_mm, move->y_mm, false, 2.0));
    ASSERT_TRUE(next.has_value());
    EXPECT_EQ(next->plane, Plane::kElevation);
    EXPECT_EQ(next->target, 2);
  }
  {
    MultiSheepPlanner planner{PlannerConfig{}};
    const auto move = planner.plan(make_scene({kA}));
    ASSERT_TRUE(move.has_value());
    ASSERT_TRUE(planner.on_motion_done(move->goal_id, true));
    const auto next =
        planner.plan(make_scene({to_centre(1, 250, 600)}, move->x_mm, move->y_mm, 2.0));
    ASSERT_TRUE(next.has_value());
    EXPECT_EQ(next->target, -1);  // nobody left to save: park
  }
}

// While the tool is down the arm hides the sheep: the world model dead-
// reckons it with its old velocity and the turn is not seen. The predicted
// body over the tool for touch_confirm_s counts as the touch.
TEST(MultiSheepPlannerTest, HiddenSheepUnderTheLoweredToolCountsAsTurned) {
  const PlannerConfig config;
  MultiSheepPlanner planner{config};
  const auto move = planner.plan(make_scene({kA}));
  ASSERT_TRUE(planner.on_motion_done(move->goal_id, true));
  const auto lower = planner.plan(advance({kA}, 2.0, move->x_mm, move->y_mm, false, 2.0));
  ASSERT_TRUE(lower.has_value() && lower->plane == Plane::kObject);
  ASSERT_TRUE(planner.on_motion_done(lower->goal_id, true));
  // The sheep's centre 30 mm short of the tool, still "walking out", obscured.
  Sheep hidden = kA;
  hidden.x_mm = lower->x_mm + 30.0;
  hidden.y_mm = lower->y_mm;
  hidden.state = SheepState::kObscured;
  Scene s = make_scene({hidden}, lower->x_mm, lower->y_mm, 10.0);
  s.arm.lowered = true;
  EXPECT_FALSE(planner.plan(s).has_value());  // body just arrived over the tool
  hidden.x_mm -= 30.0 * 0.1;
  s.sheep = {hidden};
  s.now_s = 10.1;
  EXPECT_FALSE(planner.plan(s).has_value());
  hidden.x_mm -= 30.0 * (config.touch_confirm_s);
  s.sheep = {hidden};
  s.now_s = 10.1 + config.touch_confirm_s;
  const auto raise = planner.plan(s);
  ASSERT_TRUE(raise.has_value());
  EXPECT_EQ(raise->plane, Plane::kElevation);
  EXPECT_EQ(planner.status().saves, 1);

  // Raised; the world model still shows the old velocity for a few frames:
  // the sheep just saved is not chosen again at once (nobody else: park).
  ASSERT_TRUE(planner.on_motion_done(raise->goal_id, true));
  hidden.state = SheepState::kVisible;
  Scene up = make_scene({hidden}, raise->x_mm, raise->y_mm, s.now_s + 0.7);
  const auto next = planner.plan(up);
  ASSERT_TRUE(next.has_value());
  EXPECT_EQ(next->target, -1);
  EXPECT_EQ(planner.status().phase, "parking");
  // After the cool-down a sheep still walking out is a candidate again.
  ASSERT_TRUE(planner.on_motion_done(next->goal_id, true));
  up.now_s += config.resave_cooldown_s;
  up.arm.x_mm = next->x_mm;
  up.arm.y_mm = next->y_mm;
  const auto again = planner.plan(up);
  ASSERT_TRUE(again.has_value());
  EXPECT_EQ(again->target, 1);
}

// A sheep saved while hidden that stays hidden (the raised arm still over it)
// keeps the world model's velocity from before the touch: it is no candidate
// after the cool-down either, until seen again. Issue 13's whole-system run
// lowered onto such a sheep every 3 s for 25 s.
TEST(MultiSheepPlannerTest, SheepSavedWhileHiddenIsNoCandidateUntilSeenAgain) {
  const PlannerConfig config;
  MultiSheepPlanner planner{config};
  const auto lower = move_and_lower(planner, kA);
  ASSERT_TRUE(lower.has_value());
  Sheep hidden = kA;  // over the tool, obscured, still "walking out"
  hidden.x_mm = lower->x_mm;
  hidden.y_mm = lower->y_mm;
  hidden.state = SheepState::kObscured;
  Scene s = make_scene({hidden}, lower->x_mm, lower->y_mm, 10.0);
  s.arm.lowered = true;
  EXPECT_FALSE(planner.plan(s).has_value());
  s.now_s += config.touch_confirm_s + 0.05;
  const auto raise = planner.plan(s);
  ASSERT_TRUE(raise.has_value());
  ASSERT_EQ(planner.status().saves, 1);
  ASSERT_TRUE(planner.on_motion_done(raise->goal_id, true));
  // Long after the cool-down, still hidden: parked or parking, never back.
  Scene up =
      make_scene({hidden}, raise->x_mm, raise->y_mm, s.now_s + 3.0 * config.resave_cooldown_s);
  for (int i = 0; i < 3; ++i) {
    const auto g = planner.plan(up);
    if (g) {
      EXPECT_EQ(g->target, -1) << "went back to a sheep saved and not seen since";
      ASSERT_TRUE(planner.on_motion_done(g->goal_id, true));
      up.arm.x_mm = g->x_mm;
      up.arm.y_mm = g->y_mm;
    }
    up.now_s += 1.0;
  }
  // Seen again and still walking out: a candidate again.
  hidden.state = SheepState::kVisible;
  up.sheep = {hidden};
  const auto again = planner.plan(up);
  ASSERT_TRUE(again.has_value());
  EXPECT_EQ(again->target, 1);
}

TEST(MultiSheepPlannerTest, LoweredToolIsRaisedWhenTheTargetDisappears) {
  MultiSheepPlanner planner{PlannerConfig{}};
  const auto move = planner.plan(make_scene({kA}));
  ASSERT_TRUE(planner.on_motion_done(move->goal_id, true));
  const auto lower = planner.plan(advance({kA}, 2.0, move->x_mm, move->y_mm, false, 2.0));
  ASSERT_TRUE(lower.has_value() && lower->plane == Plane::kObject);
  ASSERT_TRUE(planner.on_motion_done(lower->goal_id, true));
  const auto raise = planner.plan(make_scene({}, lower->x_mm, lower->y_mm, 3.0));
  ASSERT_TRUE(raise.has_value());
  EXPECT_EQ(raise->plane, Plane::kElevation);
  EXPECT_EQ(planner.status().phase, "raising");
  EXPECT_EQ(planner.status().saves, 0);
}

TEST(MultiSheepPlannerTest, FailedLoweringRaisesFirst) {
  MultiSheepPlanner planner{PlannerConfig{}};
  const auto move = planner.plan(make_scene({kA}));
  ASSERT_TRUE(planner.on_motion_done(move->goal_id, true));
  const auto lower = planner.plan(advance({kA}, 2.0, move->x_mm, move->y_mm, false, 2.0));
  ASSERT_TRUE(lower.has_value() && lower->plane == Plane::kObject);
  ASSERT_TRUE(planner.on_motion_done(lower->goal_id, false));
  EXPECT_FALSE(planner.plan(advance({kA}, 3.0, move->x_mm, move->y_mm, false, 3.0)).has_value());
  const auto next = planner.plan(advance({kA}, 3.3, move->x_mm, move->y_mm, false, 3.3));
  ASSERT_TRUE(next.has_value());
  EXPECT_EQ(next->plane, Plane::kElevation);
  EXPECT_EQ(planner.status().phase, "raising");
}

TEST(MultiSheepPlannerTest, StartsByRaisingAToolThatIsDown) {
  MultiSheepPlanner planner{PlannerConfig{}};
  Scene s = make_scene({kA}, 400, 400);
  s.arm.lowered = true;
  const auto goal = planner.plan(s);
  ASSERT_TRUE(goal.has_value());
  EXPECT_EQ(goal->plane, Plane::kElevation);
  EXPECT_DOUBLE_EQ(goal->x_mm, 400.0);
  EXPECT_DOUBLE_EQ(goal->y_mm, 400.0);
}

TEST(MultiSheepPlannerTest, NonFiniteSheepAreIgnoredAndCounted) {
  MultiSheepPlanner planner{PlannerConfig{}};
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const auto goal = planner.plan(make_scene({sheep(9, nan, 100, -30, 0), kA}));
  ASSERT_TRUE(goal.has_value());
  EXPECT_EQ(goal->target, 1);
  EXPECT_EQ(planner.status().bad_sheep, 1);
  // A non-finite arm position plans nothing.
  MultiSheepPlanner other{PlannerConfig{}};
  EXPECT_FALSE(other.plan(make_scene({kA}, nan, 0)).has_value());
}

TEST(PlannerFactoryTest, MakesEveryKindAndRejectsUnknownOnes) {
  for (const std::string& kind : planner_kinds()) {
    const auto p = make_planner(kind, PlannerConfig{});
    ASSERT_NE(p, nullptr);
    EXPECT_EQ(p->kind(), kind);
  }
  EXPECT_THROW(make_planner("greedy", PlannerConfig{}), std::invalid_argument);
}

}  // namespace
}  // namespace ephor::planner
