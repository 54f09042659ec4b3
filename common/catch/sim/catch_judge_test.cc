#include "common/catch/sim/catch_judge.h"

#include <cmath>

#include <gtest/gtest.h>

namespace ephor::catching {
namespace {

// A real exit: seed 3's first ball run down its pegged board.
struct Fixture {
  CatchScenario s = CatchScenario::draw(3);
  BoardExit exit;
  Fixture() {
    BoardWorld world(s);
    world.release(s.release(0));
    exit = *world.predict_exit().exit;
  }
  BallisticCrossing truth() const {
    return ballistic_crossing(s.board, s.placement, exit.x_b_mm, exit.velocity_b_mm_s.x(),
                              exit.velocity_b_mm_s.y());
  }
};

TEST(CatchJudgeTest, CrossingAgreesWithTheSharedBallisticModel) {
  const Fixture f;
  const CatchJudge judge(f.s.board, f.s.placement);
  const auto x = judge.catch_plane_crossing(f.exit);
  EXPECT_LT((x.point_w_mm - f.truth().point_w_mm).norm(), 1e-9);
  EXPECT_NEAR(x.time_s, f.exit.time_s + f.truth().flight_s, 1e-12);
}

TEST(CatchJudgeTest, CatchesAtTheBallisticPointAndMisses40MmAway) {
  const Fixture f;
  const CatchJudge judge(f.s.board, f.s.placement);
  const Eigen::Vector3d at = f.truth().point_w_mm;
  const CatchVerdict hit = judge.judge(f.exit, at);
  EXPECT_TRUE(hit.caught) << hit.reason;
  EXPECT_EQ(hit.reason, "caught: cup 0 mm from the ball's path");
  EXPECT_NEAR(hit.miss_distance_mm, 0.0, 1e-6);

  const CatchVerdict miss = judge.judge(f.exit, at + Eigen::Vector3d(0.0, 40.0, 0.0));
  EXPECT_FALSE(miss.caught);
  EXPECT_EQ(miss.reason, "cup 40 mm from the ball's path");
  // The rim: inner radius 50 minus ball radius 20.
  EXPECT_TRUE(judge.judge(f.exit, at + Eigen::Vector3d(29.0, 0.0, 0.0)).caught);
  EXPECT_FALSE(judge.judge(f.exit, at + Eigen::Vector3d(31.0, 0.0, 0.0)).caught);
}

TEST(CatchJudgeTest, CupMustWaitAtTheCatchPlane) {
  const Fixture f;
  const CatchJudge judge(f.s.board, f.s.placement);
  const Eigen::Vector3d at = f.truth().point_w_mm;
  // 15 mm lower: the ball falls through the cup's opening a little further
  // out; aimed there, the catch counts.
  const auto lower = judge.crossing(f.exit, at.z() - 15.0);
  EXPECT_TRUE(judge.judge(f.exit, lower.point_w_mm).caught);
  const CatchVerdict high = judge.judge(f.exit, judge.crossing(f.exit, at.z() + 30.0).point_w_mm);
  EXPECT_FALSE(high.caught);
  EXPECT_EQ(high.reason, "cup not at the catch plane: 30 mm above");
  EXPECT_NEAR(high.height_error_mm, 30.0, 1e-9);
}

TEST(CatchJudgeTest, MovingCupIsJudgedWhereItIsWhenTheBallArrives) {
  const Fixture f;
  const CatchJudge judge(f.s.board, f.s.placement);
  const auto x = judge.catch_plane_crossing(f.exit);
  // Sweeping along y at 500 mm/s, through the crossing point at the crossing time.
  const CatchJudge::CupTrajectory on_time = [&](double t) {
    return Eigen::Vector3d(x.point_w_mm + Eigen::Vector3d(0.0, 500.0 * (t - x.time_s), 0.0));
  };
  EXPECT_TRUE(judge.judge(f.exit, on_time).caught);
  // 0.1 s late: 50 mm behind.
  const CatchJudge::CupTrajectory late = [&](double t) { return on_time(t - 0.1); };
  const CatchVerdict v = judge.judge(f.exit, late);
  EXPECT_FALSE(v.caught);
  EXPECT_EQ(v.reason, "cup 50 mm from the ball's path");
}

TEST(CatchJudgeTest, StalledBallIsNeverCaught) {
  const Fixture f;
  const CatchJudge judge(f.s.board, f.s.placement);
  const CatchVerdict v =
      judge.judge(std::nullopt, [](double) { return Eigen::Vector3d(500.0, 0.0, 170.0); });
  EXPECT_FALSE(v.caught);
  EXPECT_EQ(v.reason, "ball stalled on the board");
}

}  // namespace
}  // namespace ephor::catching
