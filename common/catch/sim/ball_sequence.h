#pragma once
// BallSequence: the simulator's run of balls, one after another. Waits
// gap_s, releases ball k at the scenario's k-th release point, follows it
// down the board and through its flight, has CatchJudge decide when it
// falls through the cup's plane, counts, waits, and releases the next.
// At each release it also asks the oracle (CatchCell): could an arm resting
// at the ready pose, told the exit at release, have had the cup at the catch
// point in time? That bounds what any planner can catch.
//
// Times are the world clock (s). Not thread-safe: the simulator's mutex.

#include <cmath>
#include <optional>
#include <string>

#include <Eigen/Core>

#include "common/catch/sim/board_world.h"
#include "common/catch/sim/catch_cell.h"
#include "common/catch/sim/catch_judge.h"

namespace ephor::catching {

class BallSequence {
 public:
  enum class Phase { kWaiting, kRolling, kFlying, kDone };

  struct Result {
    int ball = -1;
    bool caught = false;
    bool oracle_reachable = false;
    std::string reason;
    Eigen::Vector3d ball_w_mm =
        Eigen::Vector3d::Constant(std::nan(""));  // where it fell through the cup's plane
    Eigen::Vector3d cup_w_mm = Eigen::Vector3d::Constant(std::nan(""));  // the cup's opening then
  };

  // balls: how many to release (0 = endless); gap_s: pause before each
  // release; first_release_s: world time of the first release (the arm first
  // waits parked while vision finds the board, then moves to the ready point).
  BallSequence(const CatchScenario& scenario, int balls, double gap_s, double first_release_s = 0.0,
               double max_arm_wait_s = 3.0);

  // Called after every world step at world time now_s with the arm's joints;
  // arm_still: no joint moves faster than a hundredth of a rad/s.
  void step(BoardWorld& world, const CatchCell& cell, const arm::Joints& q, double now_s,
            bool arm_still = true);

  Phase phase() const { return phase_; }
  int ball() const { return ball_; }  // index of the current (or next) ball
  int done() const { return done_; }
  int caught() const { return caught_; }
  int oracle_reachable() const { return oracle_reachable_; }
  const std::optional<Result>& last() const { return last_; }
  // The current ball's exit as simulated ahead at its release.
  const std::optional<BoardExit>& expected_exit() const { return expected_exit_; }
  // Seconds since the last ball was judged once all are (kDone), else 0.
  double finished_for_s(double now_s) const;

 private:
  CatchScenario scenario_;
  CatchJudge judge_;
  int balls_;
  double gap_s_;
  double first_release_s_;
  double max_arm_wait_s_;
  Phase phase_ = Phase::kWaiting;
  int ball_ = 0;
  double phase_since_s_ = 0.0;
  int done_ = 0, caught_ = 0, oracle_reachable_ = 0;
  bool current_reachable_ = false;
  std::optional<BoardExit> expected_exit_;
  std::optional<CatchJudge::Crossing> crossing_;
  std::optional<Result> last_;
};

}  // namespace ephor::catching
