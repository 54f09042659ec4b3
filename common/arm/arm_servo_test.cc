#include "common/arm/arm_servo.h"

#include <chrono>
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "common/arm/arm_workcell.h"

namespace ephor::sim {
namespace {

using arm::Joints;

constexpr double kDt = 0.004;  // the 250 Hz servo rate

Joints start_pose() { return arm::park_joints(geometry::Workcell{}); }

// Joint 1 and joint 5 moving by `delta` along a smoothstep over `duration`, sampled every 0.1 s.
JointTrajectory smooth_move(int64_t seq, const Joints& from, const Joints& delta, double duration) {
  JointTrajectory t;
  t.seq = seq;
  for (double s = 0.0; s <= duration + 1e-9; s += 0.1) {
    const double x = s / duration;
    t.t_s.push_back(s);
    t.q.push_back(from + delta * (3 * x * x - 2 * x * x * x));
    t.qd.push_back(delta * (6 * x - 6 * x * x) / duration);
  }
  return t;
}

TEST(ArmServo, StartsAtRestAtTheParkPose) {
  ArmServo servo(arm::Puma560::default_limits(), start_pose());
  EXPECT_EQ(servo.state().q, start_pose());
  EXPECT_TRUE(servo.state().qd.isZero());
  EXPECT_EQ(servo.state().trajectory_seq, 0);
  EXPECT_FALSE(servo.state().fault);
  for (int i = 0; i < 100; ++i) servo.step(kDt);
  EXPECT_EQ(servo.state().q, start_pose());
}

TEST(ArmServo, FollowsAFeasibleTrajectoryClosely) {
  ArmServo servo(arm::Puma560::default_limits(), start_pose());
  Joints delta = Joints::Zero();
  delta(0) = 0.5, delta(4) = -0.3;
  const JointTrajectory traj = smooth_move(7, start_pose(), delta, 2.0);
  ASSERT_TRUE(servo.follow(traj));
  double worst = 0.0;
  for (int i = 1; i <= 500; ++i) {
    servo.step(kDt);
    const double t = i * kDt;
    if (t <= 2.0) {
      const double x = t / 2.0;
      const Joints want = start_pose() + delta * (3 * x * x - 2 * x * x * x);
      worst = std::max(worst, (servo.state().q - want).cwiseAbs().maxCoeff());
    }
  }
  EXPECT_LT(worst, 1e-3);
  EXPECT_FALSE(servo.state().fault) << servo.state().fault_reason;
  EXPECT_TRUE(servo.state().trajectory_done);
  EXPECT_EQ(servo.state().trajectory_seq, 7);
  EXPECT_LT((servo.state().q - (start_pose() + delta)).cwiseAbs().maxCoeff(), 1e-3);
}

TEST(ArmServo, TrapezoidAtTheLimitsIsNoFault) {
  // Joint 1 at exactly its velocity and acceleration limits (1 rad/s, 2 rad/s^2),
  // sampled every 70 ms so that the phase changes fall inside segments.
  const arm::JointLimits lim = arm::Puma560::default_limits();
  ArmServo servo(lim, start_pose());
  const double v = lim.qd_max(0), a = lim.qdd_max(0), ta = v / a, tc = 0.5, total = 2 * ta + tc;
  const auto profile = [&](double t, double& q, double& qd) {
    if (t < ta) {
      q = 0.5 * a * t * t, qd = a * t;
    } else if (t < ta + tc) {
      q = 0.5 * a * ta * ta + v * (t - ta), qd = v;
    } else {
      const double r = std::max(0.0, total - t);
      q = 0.5 * a * ta * ta * 2 + v * tc - 0.5 * a * r * r, qd = a * r;
    }
  };
  JointTrajectory traj;
  traj.seq = 3;
  for (double t = 0.0;; t = std::min(t + 0.07, total)) {
    double q, qd;
    profile(t, q, qd);
    Joints jq = start_pose(), jqd = Joints::Zero();
    jq(0) += q, jqd(0) = qd;
    traj.t_s.push_back(t), traj.q.push_back(jq), traj.qd.push_back(jqd);
    if (t >= total) break;
  }
  ASSERT_TRUE(servo.follow(traj));
  for (int i = 0; i < 600 && !servo.state().trajectory_done; ++i) servo.step(kDt);
  EXPECT_FALSE(servo.state().fault) << servo.state().fault_reason;
  EXPECT_TRUE(servo.state().trajectory_done);
  EXPECT_NEAR(servo.state().q(0), start_pose()(0) + v * (ta + tc), 1e-3);
}

TEST(ArmServo, AggressiveTrajectoryIsClampedToTheLimitsAndFaults) {
  const arm::JointLimits lim = arm::Puma560::default_limits();
  ArmServo servo(lim, start_pose());
  JointTrajectory traj;
  traj.seq = 1;
  Joints goal = start_pose();
  goal(0) += 1.2;  // in 0.1 s: 12 rad/s asked of a 1 rad/s joint
  goal(3) -= 0.8;
  traj.t_s = {0.1};
  traj.q = {goal};
  traj.qd = {Joints::Zero()};
  ASSERT_TRUE(servo.follow(traj));
  Joints prev_qd = Joints::Zero();
  double overshoot = 0.0;
  for (int i = 0; i < 1000 && !servo.state().trajectory_done; ++i) {
    servo.step(kDt);
    const auto& s = servo.state();
    for (int j = 0; j < 6; ++j) {
      ASSERT_LE(std::abs(s.qd(j)), lim.qd_max(j) + 1e-12) << "joint " << j + 1 << " step " << i;
      ASSERT_LE(std::abs(s.qd(j) - prev_qd(j)), lim.qdd_max(j) * kDt + 1e-12)
          << "joint " << j + 1 << " step " << i;
    }
    overshoot = std::max(overshoot, s.q(0) - goal(0));
    prev_qd = s.qd;
  }
  EXPECT_TRUE(servo.state().fault);
  EXPECT_NE(servo.state().fault_reason.find("velocity"), std::string::npos)
      << servo.state().fault_reason;
  EXPECT_TRUE(servo.state().trajectory_done) << "never arrived";
  EXPECT_LT(overshoot, 0.01);
}

TEST(ArmServo, OutOfLimitTrajectoryIsRefusedAndTheArmStops) {
  const arm::JointLimits lim = arm::Puma560::default_limits();
  ArmServo servo(lim, start_pose());
  Joints delta = Joints::Zero();
  delta(0) = 0.8;
  ASSERT_TRUE(servo.follow(smooth_move(1, start_pose(), delta, 2.0)));
  for (int i = 0; i < 250; ++i) servo.step(kDt);  // mid-move, joint 1 at speed
  ASSERT_GT(std::abs(servo.state().qd(0)), 0.3);
  JointTrajectory bad = smooth_move(2, servo.state().q, Joints::Zero(), 1.0);
  bad.q.back()(1) = lim.q_max(1) + 0.1;
  EXPECT_FALSE(servo.follow(bad));
  EXPECT_TRUE(servo.state().fault);
  EXPECT_EQ(servo.state().trajectory_seq, 2);
  EXPECT_FALSE(servo.state().trajectory_done);
  EXPECT_NE(servo.state().fault_reason.find("joint 2"), std::string::npos)
      << servo.state().fault_reason;
  for (int i = 0; i < 250; ++i) servo.step(kDt);
  EXPECT_TRUE(servo.state().qd.isZero()) << "still moving";
  const Joints stopped = servo.state().q;
  for (int i = 0; i < 250; ++i) servo.step(kDt);
  EXPECT_EQ(servo.state().q, stopped);
  // A good trajectory clears the fault.
  ASSERT_TRUE(servo.follow(smooth_move(3, stopped, -delta * 0.5, 2.0)));
  EXPECT_FALSE(servo.state().fault);
}

TEST(ArmServo, DuplicateSeqIsIgnoredAndNewestWins) {
  ArmServo servo(arm::Puma560::default_limits(), start_pose());
  Joints delta = Joints::Zero();
  delta(2) = 0.3;
  const auto a = smooth_move(5, start_pose(), delta, 1.0);
  ASSERT_TRUE(servo.follow(a));
  servo.step(kDt);
  EXPECT_FALSE(servo.follow(a));
  const auto b = smooth_move(6, servo.state().q, -delta, 1.0);
  EXPECT_TRUE(servo.follow(b));
  EXPECT_EQ(servo.state().trajectory_seq, 6);
}

// Found by the fuzz target catch_sim (procs/catch/sim): a trajectory asking
// 6e270 rad/s of joint 1 faults at once, and every step after formatted the
// demands again (270-digit numbers, only to be dropped: the first reason is
// kept), a fifth of a millisecond a step and more, so ephor-catch-sim's
// physics fell behind the clock.
TEST(ArmServo, ALatchedFaultIsNotFormattedAgainEveryStep) {
  ArmServo servo(arm::Puma560::default_limits(), start_pose());
  JointTrajectory t;
  t.seq = 1;
  t.t_s = {0.0, 10.0, 20.0};
  t.q = {start_pose(), start_pose(), start_pose()};
  Joints fast = Joints::Zero();
  fast(0) = -6.1e270;
  fast(3) = -2.5e235;
  t.qd = {fast, fast, Joints::Zero()};
  ASSERT_TRUE(servo.follow(t));
  ASSERT_TRUE(servo.state().fault);
  const std::string reason = servo.state().fault_reason;
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < 20000; ++i) servo.step(0.001);
  const double took_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(servo.state().fault_reason, reason);
  EXPECT_TRUE(servo.limits().within(servo.state().q));
  EXPECT_LT(took_s, 0.5) << "20 000 steps of 1 ms took " << took_s << " s";
}

TEST(ArmServo, MalformedTrajectoriesAreNamed) {
  JointTrajectory t = smooth_move(1, start_pose(), Joints::Zero(), 1.0);
  EXPECT_FALSE(malformed(t).has_value());
  auto nan = t;
  nan.q[3](2) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(*malformed(nan), "q[3] is not finite");
  auto order = t;
  order.t_s[4] = order.t_s[3];
  EXPECT_NE(malformed(order)->find("not increasing at point 4"), std::string::npos);
  auto sizes = t;
  sizes.qd.pop_back();
  EXPECT_TRUE(malformed(sizes).has_value());
  EXPECT_TRUE(malformed(JointTrajectory{}).has_value());
  ArmServo servo(arm::Puma560::default_limits(), start_pose());
  EXPECT_THROW(servo.step(0.0), std::invalid_argument);
}

}  // namespace
}  // namespace ephor::sim
