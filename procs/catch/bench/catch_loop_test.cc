#include "procs/catch/bench/catch_loop.h"

#include <gtest/gtest.h>

#include "common/catch/board_file.h"
#include "common/config/repo_paths.h"
#include "common/geometry/workcell_file.h"

namespace ephor::catching {
namespace {

BoardSpec board() { return load_board_file(resolve_repo_path("deploy/catch/board.pbtxt")); }
geometry::Workcell workcell() {
  return geometry::load_workcell_file(resolve_repo_path("deploy/catch/workcell.pbtxt"));
}

// Told each ball's catch point at its release, the arm as ephor-arm and the
// servo execute the goal catches every ball the simulator's oracle counts as
// reachable: the loop's arm, timing and judge agree with the oracle's.
TEST(CatchLoopTest, AnOracleGoalCatchesEveryReachableBall) {
  CatchLoopOptions o;
  o.seed = 2;
  o.balls = 4;
  o.first_release_s = 4.0;  // the arm is at the ready point by then
  o.true_centre = true;
  o.prim = PrimMode::kOracle;
  const CatchLoopResult r = CatchLoop(board(), workcell(), o).run();
  EXPECT_EQ(r.balls, 4);
  EXPECT_GT(r.oracle_reachable, 0);
  EXPECT_EQ(r.caught_reachable, r.oracle_reachable) << r.summary.dump(1);
  EXPECT_EQ(r.plans_refused, 0);
}

// The same options give the same run, ball for ball (simulated time only).
TEST(CatchLoopTest, IsDeterministic) {
  CatchLoopOptions o;
  o.seed = 3;
  o.balls = 1;
  o.first_release_s = 4.0;
  const CatchLoopResult a = CatchLoop(board(), workcell(), o).run();
  const CatchLoopResult b = CatchLoop(board(), workcell(), o).run();
  EXPECT_EQ(a.balls, 1);
  EXPECT_GE(a.goals, 1);  // the ready point at least
  EXPECT_EQ(a.summary.dump(), b.summary.dump());
  EXPECT_EQ(a.goals, b.goals);
}

TEST(CatchLoopTest, BadOptionsAreRefused) {
  CatchLoopOptions o;
  o.balls = 0;
  EXPECT_THROW(CatchLoop(board(), workcell(), o), std::invalid_argument);
  o.balls = 1;
  o.command_latency_s = -0.001;
  EXPECT_THROW(CatchLoop(board(), workcell(), o), std::invalid_argument);
}

}  // namespace
}  // namespace ephor::catching
