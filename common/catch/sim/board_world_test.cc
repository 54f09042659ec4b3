#include "common/catch/sim/board_world.h"

#include <cmath>
#include <numbers>
#include <stdexcept>

#include <gtest/gtest.h>

namespace ephor::catching {
namespace {

constexpr double kFrameS = 1.0 / 60.0;

// Steps at the camera's rate until the ball is off the board or stalled.
void run_to_exit(BoardWorld& world, double dt = kFrameS) {
  for (int i = 0; i < 100000 && !world.exit() && !world.stalled(); ++i) world.step(dt);
}

TEST(BoardWorldTest, BareBoardMatchesRollingSphereModel) {
  const BoardSpec board;
  const double incline = 25.0 * std::numbers::pi / 180.0;
  BoardWorld world(board, incline, {}, 12.0);
  world.step(0.5);  // the clock runs before the release too
  const double y0 = 30.0;
  world.release(300.0, y0, 0.0, 0.0);
  run_to_exit(world);
  ASSERT_TRUE(world.exit().has_value());
  const double a = 5.0 / 7.0 * 9810.0 * std::sin(incline);
  EXPECT_DOUBLE_EQ(world.slope_acceleration_mm_s2(), a);
  const double t = std::sqrt(2.0 * (board.height_mm - y0) / a);
  EXPECT_NEAR(world.exit()->time_s - 0.5, t, 0.01 * t);
  EXPECT_NEAR(world.exit()->velocity_b_mm_s.y(), a * t, 0.01 * a * t);
  EXPECT_NEAR(world.exit()->velocity_b_mm_s.x(), 0.0, 1e-6);
  EXPECT_NEAR(world.exit()->x_b_mm, 300.0, 1e-3);
}

TEST(BoardWorldTest, PredictExitEqualsTheExitTheWorldReaches) {
  for (uint64_t seed = 1; seed <= 10; ++seed) {
    const CatchScenario s = CatchScenario::draw(seed);
    BoardWorld world(s);
    world.step(0.1);
    world.release(s.release(0));
    const SimulatedExit at_release = world.predict_exit();
    for (int i = 0; i < 20; ++i) world.step(kFrameS);
    const SimulatedExit midway = world.predict_exit();
    const BallState before = world.state();
    const SimulatedExit again = world.predict_exit();
    EXPECT_EQ(before.position_b_mm, world.state().position_b_mm)
        << "prediction disturbed the world";
    run_to_exit(world);
    ASSERT_TRUE(world.exit().has_value()) << "seed " << seed;
    for (const SimulatedExit* p : {&at_release, &midway, &again}) {
      ASSERT_TRUE(p->exit.has_value()) << "seed " << seed;
      EXPECT_FALSE(p->stalled);
      EXPECT_EQ(p->exit->time_s, world.exit()->time_s) << "seed " << seed;
      EXPECT_EQ(p->exit->x_b_mm, world.exit()->x_b_mm) << "seed " << seed;
      EXPECT_EQ(p->exit->velocity_b_mm_s, world.exit()->velocity_b_mm_s) << "seed " << seed;
    }
  }
}

TEST(BoardWorldTest, TrajectoryDoesNotDependOnHowTheClockIsStepped) {
  const CatchScenario s = CatchScenario::draw(4);
  BoardWorld frames(s), fine(s);
  frames.release(s.release(2));
  fine.release(s.release(2));
  run_to_exit(frames, kFrameS);
  run_to_exit(fine, 0.00025);
  ASSERT_TRUE(frames.exit() && fine.exit());
  EXPECT_NEAR(frames.exit()->time_s, fine.exit()->time_s, 1e-9);
  EXPECT_NEAR(frames.exit()->x_b_mm, fine.exit()->x_b_mm, 1e-9);
}

TEST(BoardWorldTest, PegsDeflectTheBallAndRailsKeepItOnTheBoard) {
  int deflected = 0;
  for (uint64_t seed = 1; seed <= 10; ++seed) {
    const CatchScenario s = CatchScenario::draw(seed);
    const double r = s.board.ball_radius_mm();
    for (int k = 0; k < 3; ++k) {
      BoardWorld world(s);
      const BallRelease rel = s.release(k);
      world.release(rel);
      while (!world.exit() && !world.stalled()) {
        world.step(0.005);
        const BallState st = world.state();
        if (!st.on_board) break;
        ASSERT_GE(st.position_b_mm.x(), r - 0.5) << "seed " << seed << " ball " << k;
        ASSERT_LE(st.position_b_mm.x(), s.board.width_mm - r + 0.5) << "seed " << seed;
        ASSERT_GE(st.position_b_mm.y(), r - 0.5) << "seed " << seed;
      }
      ASSERT_TRUE(world.exit().has_value()) << "seed " << seed << " ball " << k << " stalled";
      if (std::abs(world.exit()->x_b_mm - rel.x_mm) > 5.0) ++deflected;
    }
  }
  EXPECT_GT(deflected, 10);  // of 30 balls
}

TEST(BoardWorldTest, FlightAfterTheEdgeFallsUnderFullGravity) {
  const CatchScenario s = CatchScenario::draw(2);
  BoardWorld world(s);
  world.release(s.release(0));
  run_to_exit(world);
  ASSERT_TRUE(world.exit().has_value());
  world.step(0.1);
  const BallState st = world.state();
  EXPECT_FALSE(st.on_board);
  const double tau = st.time_s - world.exit()->time_s;
  const Pose b2w = s.board_to_world();
  const Eigen::Vector3d v_w = b2w.linear() * st.velocity_b_mm_s;
  const Eigen::Vector3d v0_w =
      b2w.linear() *
      Eigen::Vector3d(world.exit()->velocity_b_mm_s.x(), world.exit()->velocity_b_mm_s.y(), 0.0);
  EXPECT_NEAR(v_w.z(), v0_w.z() - 9810.0 * tau, 1e-6);
  EXPECT_NEAR(v_w.x(), v0_w.x(), 1e-6);
}

TEST(BoardWorldTest, BallWedgedBetweenPegsStalls) {
  // Two pegs 30 mm apart (closer than the ball's 40 mm) under the release point.
  const BoardSpec board;
  BoardWorldConfig config;
  config.stall_limit_s = 2.0;
  BoardWorld world(board, 0.4, {{285.0, 200.0}, {315.0, 200.0}}, 12.0, config);
  world.release(300.0, 100.0, 0.0, 0.0);
  const SimulatedExit p = world.predict_exit();
  EXPECT_TRUE(p.stalled);
  EXPECT_FALSE(p.exit.has_value());
  run_to_exit(world);
  EXPECT_TRUE(world.stalled());
  EXPECT_FALSE(world.exit().has_value());
  // Resting on both pegs: centre 20 + 6 mm from each.
  EXPECT_NEAR(world.state().position_b_mm.y(), 200.0 - std::sqrt(26.0 * 26.0 - 15.0 * 15.0), 1.0);
  EXPECT_NEAR(world.state().position_b_mm.x(), 300.0, 1.0);
}

TEST(BoardWorldTest, RejectsBadInput) {
  const BoardSpec board;
  EXPECT_THROW(BoardWorld(board, 0.0, {}, 12.0), std::invalid_argument);
  EXPECT_THROW(BoardWorld(board, 0.4, {{-5.0, 100.0}}, 12.0), std::invalid_argument);
  BoardWorld world(board, 0.4, {{300.0, 300.0}}, 12.0);
  EXPECT_THROW(world.release(10.0, 100.0, 0.0, 0.0), std::invalid_argument);   // off the board
  EXPECT_THROW(world.release(300.0, 310.0, 0.0, 0.0), std::invalid_argument);  // inside the peg
  EXPECT_THROW(world.predict_exit(), std::logic_error);
  EXPECT_FALSE(world.state().released);
}

}  // namespace
}  // namespace ephor::catching
