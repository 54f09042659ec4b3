#include "common/catch/worldmodel/ball_measurement_gate.h"

#include <cmath>

#include <gtest/gtest.h>

#include "common/catch/worldmodel/test_scene.h"

namespace ephor::catching {
namespace {

constexpr double kFrame = 1.0 / 60.0;  // s, 16.7 ms

class BallMeasurementGateTest : public ::testing::Test {
 protected:
  BoardSpec board_;
  BoardPlacement placement_;
};

TEST_F(BallMeasurementGateTest, LimitComesFromTheIncline) {
  const BallMeasurementGate gate(board_, placement_);
  const double a = 5.0 / 7.0 * kGravityMmS2 * std::sin(placement_.incline_rad);
  EXPECT_NEAR(gate.rolling_acceleration_mm_s2(), a, 1e-9);
  EXPECT_NEAR(gate.max_speed_mm_s(), std::sqrt(2.0 * a * board_.height_mm), 1e-9);
  // 25 degrees, 900 mm: ~2.3 m/s at the bottom; ~50 mm allowed per frame.
  EXPECT_NEAR(gate.max_speed_mm_s(), 2309.0, 5.0);
  EXPECT_GT(gate.jump_limit_mm(kFrame), 40.0);
  EXPECT_LT(gate.jump_limit_mm(kFrame), 60.0);
}

TEST_F(BallMeasurementGateTest, RejectsAPointOffTheBoard) {
  BallMeasurementGate gate(board_, placement_);
  const GateDecision left = gate.check(0.0, Eigen::Vector2d(-30.0, 400.0));
  EXPECT_FALSE(left.accepted);
  EXPECT_EQ(left.reason, RejectReason::kOffBoard);
  EXPECT_FALSE(gate.check(0.1, Eigen::Vector2d(300.0, board_.height_mm + 25.0)).accepted);
  EXPECT_EQ(gate.rejected(RejectReason::kOffBoard), 2);
  // Within the margin is on the board (a centroid of a ball at the edge).
  EXPECT_TRUE(gate.check(0.2, Eigen::Vector2d(-5.0, 400.0)).accepted);
}

TEST_F(BallMeasurementGateTest, RejectsA200MmJumpInOneFrame) {
  BallMeasurementGate gate(board_, placement_);
  ASSERT_TRUE(gate.check(0.0, Eigen::Vector2d(300.0, 400.0)).acquired);
  const GateDecision jump = gate.check(kFrame, Eigen::Vector2d(300.0, 600.0));
  EXPECT_FALSE(jump.accepted);
  EXPECT_EQ(jump.reason, RejectReason::kJump);
  EXPECT_NEAR(jump.jump_mm, 200.0, 1e-9);
  EXPECT_EQ(gate.rejected(RejectReason::kJump), 1);
  // The ball itself, one more frame on, is still accepted against the old
  // reference (the window has opened to two frames).
  const GateDecision next = gate.check(2.0 * kFrame, Eigen::Vector2d(302.0, 430.0));
  EXPECT_TRUE(next.accepted);
  EXPECT_FALSE(next.acquired);
}

TEST_F(BallMeasurementGateTest, AcceptsEveryPointOfARealRollingBall) {
  const double a = testing::rolling_acceleration(placement_);
  // Released near the top with a small sideways push, a peg bounce half way
  // down (back up the slope and sideways): all within the physics.
  const auto track = testing::simulate_roll(board_, a, {250.0, 40.0}, {150.0, 0.0}, kFrame, 1.5, 7,
                                            {{0.45, Eigen::Vector2d(-250.0, -500.0)}});
  ASSERT_GT(track.size(), 40u);
  BallMeasurementGate gate(board_, placement_);
  for (const auto& s : track) {
    const GateDecision d = gate.check(s.t_s, s.measured_mm);
    EXPECT_TRUE(d.accepted) << "t=" << s.t_s << " reason " << to_string(d.reason) << " jump "
                            << d.jump_mm << " limit " << d.limit_mm;
  }
  EXPECT_EQ(gate.rejected_total(), 0);
  EXPECT_EQ(gate.acquisitions(), 1);
}

TEST_F(BallMeasurementGateTest, ReacquiresANewBallAfterConsecutiveRejections) {
  BallGateParams params;
  params.reacquire_after = 3;
  BallMeasurementGate gate(board_, placement_, params);
  ASSERT_TRUE(gate.check(0.0, Eigen::Vector2d(300.0, 850.0)).accepted);
  // A new ball at the top: far from the old reference for three frames.
  for (int k = 1; k <= 3; ++k) {
    EXPECT_EQ(gate.check(k * kFrame, Eigen::Vector2d(100.0, 30.0)).reason, RejectReason::kJump);
  }
  const GateDecision d = gate.check(4 * kFrame, Eigen::Vector2d(100.0, 31.0));
  EXPECT_TRUE(d.accepted);
  EXPECT_TRUE(d.acquired);
  EXPECT_EQ(gate.acquisitions(), 2);
}

TEST_F(BallMeasurementGateTest, CountsReasonsAndRejectsOutOfOrderAndNaN) {
  BallMeasurementGate gate(board_, placement_);
  ASSERT_TRUE(gate.check(1.0, Eigen::Vector2d(300.0, 400.0)).accepted);
  EXPECT_EQ(gate.check(1.0, Eigen::Vector2d(300.0, 401.0)).reason, RejectReason::kOutOfOrder);
  EXPECT_EQ(gate.check(1.1, Eigen::Vector2d(std::nan(""), 401.0)).reason, RejectReason::kNotFinite);
  gate.note_rejection(RejectReason::kNoIntersection);
  EXPECT_EQ(gate.rejected(RejectReason::kOutOfOrder), 1);
  EXPECT_EQ(gate.rejected(RejectReason::kNotFinite), 1);
  EXPECT_EQ(gate.rejected(RejectReason::kNoIntersection), 1);
  EXPECT_EQ(gate.rejected_total(), 3);
  EXPECT_EQ(gate.accepted(), 1);
}

TEST_F(BallMeasurementGateTest, RejectsBadConfiguration) {
  placement_.incline_rad = 0.0;
  EXPECT_THROW(BallMeasurementGate(board_, placement_), std::invalid_argument);
}

}  // namespace
}  // namespace ephor::catching
