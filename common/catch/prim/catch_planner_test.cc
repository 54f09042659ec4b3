#include "common/catch/prim/catch_planner.h"

#include <cmath>

#include <gtest/gtest.h>

namespace ephor::catching {
namespace {

constexpr int64_t kMs = 1000;  // us

class CatchPlannerTest : public ::testing::Test {
 protected:
  CatchPlannerTest() : params_(CatchPlannerParams::for_board(board_, placement_)) {}
  CatchPlanner make() { return CatchPlanner(board_, placement_, params_); }
  // A ball due at 700 ms, 100 mm in front of the edge and 40 mm to the side.
  CatchPrediction prediction(double dy_mm = 0.0, double sigma_mm = 3.0) const {
    CatchPrediction p;
    p.ball_id = 1;
    p.catch_utime = 700 * kMs;
    p.catch_point_w_mm = placement_.bottom_centre_w_mm +
                         Eigen::Vector3d(-100.0, 40.0 + dy_mm, -kCatchPlaneBelowEdgeMm);
    p.sigma_mm = sigma_mm;
    return p;
  }

  BoardSpec board_;
  BoardPlacement placement_;
  CatchPlannerParams params_;
  Eigen::Vector3d cup_{400.0, 0.0, 300.0};
};

TEST_F(CatchPlannerTest, WaitsAtTheReadyPointBeforeABallIsSeen) {
  CatchPlanner planner = make();
  // In the catch plane, in front of the edge's centre where balls fall through it.
  const Eigen::Vector3d ready = ready_point_w_mm(board_, placement_);
  EXPECT_EQ(planner.ready_point_w_mm(), ready);
  EXPECT_NEAR(ready.z(), placement_.bottom_centre_w_mm.z() - kCatchPlaneBelowEdgeMm, 1e-9);
  EXPECT_NEAR(ready.y(), placement_.bottom_centre_w_mm.y(), 1e-9);
  EXPECT_LT(ready.x(), placement_.bottom_centre_w_mm.x() - 80.0);
  const CatchGoal first = planner.step(0, std::nullopt, cup_);
  EXPECT_TRUE(first.send);
  EXPECT_EQ(first.reason, GoalReason::kReady);
  EXPECT_EQ(first.goal_id, 1);
  EXPECT_EQ(first.point_w_mm, ready);
  EXPECT_FALSE(first.clamped);
  EXPECT_NEAR(first.cup_distance_mm, (cup_ - ready).norm(), 1e-9);
  const CatchGoal again = planner.step(100 * kMs, std::nullopt, cup_);
  EXPECT_FALSE(again.send);
  EXPECT_EQ(again.reason, GoalReason::kUnchanged);
  EXPECT_EQ(again.goal_id, 1);
}

TEST_F(CatchPlannerTest, GoesToThePredictionAndResendsOnlyForChangesThatMatter) {
  CatchPlanner planner = make();
  planner.step(0, std::nullopt, cup_);
  const CatchGoal catch_goal = planner.step(100 * kMs, prediction(), cup_);
  EXPECT_TRUE(catch_goal.send);
  EXPECT_EQ(catch_goal.reason, GoalReason::kCatch);
  EXPECT_EQ(catch_goal.goal_id, 2);
  EXPECT_EQ(catch_goal.point_w_mm, prediction().catch_point_w_mm);
  EXPECT_NEAR(catch_goal.time_to_catch_s, 0.6, 1e-9);

  // 1 mm: not re-sent, not even after the refresh period.
  const CatchGoal small = planner.step(150 * kMs, prediction(1.0), cup_);
  EXPECT_FALSE(small.send);
  EXPECT_EQ(small.reason, GoalReason::kUnchanged);
  EXPECT_NEAR(small.moved_mm, 1.0, 1e-9);
  EXPECT_DOUBLE_EQ(small.threshold_mm, 5.0);
  EXPECT_FALSE(planner.step(400 * kMs, prediction(1.0), cup_).send);

  // 30 mm: re-sent at once.
  const CatchGoal big = planner.step(420 * kMs, prediction(30.0), cup_);
  EXPECT_TRUE(big.send);
  EXPECT_EQ(big.reason, GoalReason::kRefined);
  EXPECT_EQ(big.goal_id, 3);
  EXPECT_NEAR(big.point_w_mm.y(), prediction(30.0).catch_point_w_mm.y(), 1e-9);

  // 3 mm: below the threshold, sent as a refresh once the period passed.
  EXPECT_FALSE(planner.step(450 * kMs, prediction(33.0), cup_).send);
  const CatchGoal refresh = planner.step(530 * kMs, prediction(33.0), cup_);
  EXPECT_TRUE(refresh.send);
  EXPECT_EQ(refresh.reason, GoalReason::kRefreshed);
}

TEST_F(CatchPlannerTest, ThresholdGrowsWithTheSigmaOfThePrediction) {
  CatchPlanner planner = make();
  planner.step(0, std::nullopt, cup_);
  planner.step(100 * kMs, prediction(0.0, 100.0), cup_);
  // sigma 100 mm: threshold 30 mm; a 20 mm change of an uncertain
  // prediction waits for the refresh.
  const CatchGoal g = planner.step(150 * kMs, prediction(20.0, 100.0), cup_);
  EXPECT_DOUBLE_EQ(g.threshold_mm, 30.0);
  EXPECT_FALSE(g.send);
}

TEST_F(CatchPlannerTest, NeverSendsMoreOftenThanTheMinimumInterval) {
  CatchPlanner planner = make();
  planner.step(0, std::nullopt, cup_);
  ASSERT_TRUE(planner.step(100 * kMs, prediction(), cup_).send);
  const CatchGoal soon = planner.step(110 * kMs, prediction(30.0), cup_);
  EXPECT_FALSE(soon.send);
  EXPECT_EQ(soon.reason, GoalReason::kTooSoon);
  EXPECT_EQ(soon.goal_id, 2);
  const CatchGoal later = planner.step(130 * kMs, prediction(30.0), cup_);
  EXPECT_TRUE(later.send);
  EXPECT_EQ(later.reason, GoalReason::kRefined);
}

TEST_F(CatchPlannerTest, ClampsAnOutOfReachPredictionAndSaysSo) {
  CatchPlanner planner = make();
  planner.step(0, std::nullopt, cup_);
  // 600 mm to the side of the board's centre line: beyond the box's 400 mm.
  const CatchGoal g = planner.step(100 * kMs, prediction(560.0), cup_);
  EXPECT_TRUE(g.send);
  EXPECT_TRUE(g.clamped);
  EXPECT_NEAR(g.clamped_by_mm, 200.0, 1e-9);
  EXPECT_DOUBLE_EQ(g.point_w_mm.y(), params_.reach_max_w_mm.y());
  EXPECT_EQ(g.wanted_w_mm, prediction(560.0).catch_point_w_mm);
}

TEST_F(CatchPlannerTest, ReturnsToReadyAfterTheBallHasGone) {
  CatchPlanner planner = make();
  planner.step(0, std::nullopt, cup_);
  planner.step(100 * kMs, prediction(), cup_);
  // The world model keeps repeating the exited ball's prediction.
  const CatchGoal hold = planner.step(800 * kMs, prediction(), cup_);
  EXPECT_FALSE(hold.send);
  EXPECT_EQ(hold.reason, GoalReason::kHolding);
  const CatchGoal back = planner.step(1250 * kMs, prediction(), cup_);
  EXPECT_TRUE(back.send);
  EXPECT_EQ(back.reason, GoalReason::kReturnReady);
  EXPECT_EQ(back.point_w_mm, planner.ready_point_w_mm());
  EXPECT_FALSE(planner.step(1300 * kMs, prediction(), cup_).send);
  // The next ball is aimed at again.
  CatchPrediction next = prediction(-80.0);
  next.ball_id = 2;
  next.catch_utime = 2000 * kMs;
  const CatchGoal g = planner.step(1400 * kMs, next, cup_);
  EXPECT_TRUE(g.send);
  EXPECT_EQ(g.reason, GoalReason::kCatch);
}

TEST_F(CatchPlannerTest, RejectsABoxWithoutTheReadyPoint) {
  params_.reach_max_w_mm.x() = ready_point_w_mm(board_, placement_).x() - 10.0;
  EXPECT_THROW(make(), std::invalid_argument);
}

TEST_F(CatchPlannerTest, DoesNotReaimInTheLastMomentsBeforeTheCatch) {
  params_.freeze_before_catch_s = 0.15;
  params_.min_interval_us = 0;
  CatchPlanner planner = make();
  planner.step(0, std::nullopt, cup_);
  EXPECT_EQ(planner.step(100 * kMs, prediction(), cup_).reason, GoalReason::kCatch);
  // 0.4 s ahead a 50 mm change is re-aimed at; 0.1 s ahead it is not.
  const CatchGoal early = planner.step(300 * kMs, prediction(50.0), cup_);
  EXPECT_TRUE(early.send);
  EXPECT_EQ(early.reason, GoalReason::kRefined);
  const CatchGoal late = planner.step(600 * kMs, prediction(120.0), cup_);
  EXPECT_FALSE(late.send);
  EXPECT_EQ(late.reason, GoalReason::kFrozen);
  EXPECT_EQ(late.point_w_mm, prediction(50.0).catch_point_w_mm);
  // A new ball's first goal still goes, however near its catch.
  CatchPrediction next = prediction(-30.0);
  next.ball_id = 2;
  EXPECT_EQ(planner.step(650 * kMs, next, cup_).reason, GoalReason::kCatch);
}

// Commit late: with the cup at the ready point, a catch 40 mm to the side
// needs 0.089 * sqrt(40) = 0.56 s of move; with a 0.1 s margin the first goal
// waits while the catch is more than 0.66 s ahead, then goes; a re-aim goes
// only while the arm could still get there.
TEST_F(CatchPlannerTest, CommitsLateEnoughForTheArmToGetThere) {
  params_.move_s_per_sqrt_mm = 0.089;
  params_.commit_margin_s = 0.1;
  params_.min_interval_us = 0;
  CatchPlanner planner = make();
  const Eigen::Vector3d ready = planner.ready_point_w_mm();
  planner.step(0, std::nullopt, ready);
  CatchPrediction p = prediction();
  p.catch_point_w_mm = ready + Eigen::Vector3d(0.0, 40.0, 0.0);
  p.catch_utime = 1000 * kMs;
  const CatchGoal wait = planner.step(300 * kMs, p, ready);  // 0.7 s ahead
  EXPECT_FALSE(wait.send);
  EXPECT_EQ(wait.reason, GoalReason::kWaiting);
  EXPECT_NEAR(wait.move_time_s, 0.089 * std::sqrt(40.0), 1e-9);
  EXPECT_EQ(wait.point_w_mm, ready);
  const CatchGoal go = planner.step(350 * kMs, p, ready);  // 0.65 s ahead
  EXPECT_TRUE(go.send);
  EXPECT_EQ(go.reason, GoalReason::kCatch);
  // 30 mm the other way (0.49 s from the cup at the ready point) with 0.6 s
  // left: re-aimed; 200 mm away (1.26 s of move) with 0.55 s left: out of time.
  CatchPrediction near = p;
  near.catch_point_w_mm = ready + Eigen::Vector3d(0.0, -30.0, 0.0);
  EXPECT_EQ(planner.step(400 * kMs, near, ready).reason, GoalReason::kRefined);
  CatchPrediction far = p;
  far.catch_point_w_mm = ready + Eigen::Vector3d(0.0, 200.0, 0.0);
  const CatchGoal out = planner.step(450 * kMs, far, ready);
  EXPECT_FALSE(out.send);
  EXPECT_EQ(out.reason, GoalReason::kOutOfTime);
  EXPECT_EQ(out.point_w_mm, near.catch_point_w_mm);
}

TEST_F(CatchPlannerTest, RefusesANegativeFreeze) {
  params_.freeze_before_catch_s = -0.1;
  EXPECT_THROW(make(), std::invalid_argument);
  params_.freeze_before_catch_s = 0.0;
  params_.move_s_per_sqrt_mm = -1.0;
  EXPECT_THROW(make(), std::invalid_argument);
}

}  // namespace
}  // namespace ephor::catching
