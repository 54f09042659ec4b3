#include "common/catch/sim/ball_sequence.h"

#include <string>

#include <gtest/gtest.h>

#include "common/catch/sim/catch_scenario.h"
#include "common/geometry/workcell_file.h"

namespace ephor::catching {
namespace {

// deploy/catch/workcell.pbtxt, found from this file's place in the tree.
std::string workcell_path() {
  std::string here = __FILE__;  // .../common/catch/sim/ball_sequence_test.cc
  for (int i = 0; i < 4; ++i) here = here.substr(0, here.find_last_of('/'));
  return here + "/deploy/catch/workcell.pbtxt";
}

class BallSequenceTest : public ::testing::Test {
 protected:
  BallSequenceTest()
      : scenario_(CatchScenario::draw(1, BoardSpec{})),
        cell_(scenario_, geometry::load_workcell_file(workcell_path())),
        world_(scenario_) {}

  // Steps the sequence in 1 ms steps until `until_s`; the arm still or not.
  void run(BallSequence& balls, double until_s, bool arm_still) {
    for (; now_s_ < until_s; now_s_ += 0.001) {
      world_.step(0.001);
      balls.step(world_, cell_, cell_.ready_joints(), now_s_, arm_still);
    }
  }

  CatchScenario scenario_;
  CatchCell cell_;
  BoardWorld world_;
  double now_s_ = 0.0;
};

TEST_F(BallSequenceTest, ReleasesAfterTheGapWhenTheArmIsStill) {
  BallSequence balls(scenario_, 1, 0.5, 0.0, 2.0);
  run(balls, 0.49, true);
  EXPECT_EQ(balls.phase(), BallSequence::Phase::kWaiting);
  run(balls, 0.52, true);
  EXPECT_EQ(balls.phase(), BallSequence::Phase::kRolling);
}

TEST_F(BallSequenceTest, WaitsForAMovingArmButNotForever) {
  BallSequence balls(scenario_, 1, 0.5, 0.0, 2.0);
  run(balls, 2.4, false);
  EXPECT_EQ(balls.phase(), BallSequence::Phase::kWaiting);
  run(balls, 2.6, false);  // the gap plus the longest wait have passed
  EXPECT_EQ(balls.phase(), BallSequence::Phase::kRolling);
}

}  // namespace
}  // namespace ephor::catching
