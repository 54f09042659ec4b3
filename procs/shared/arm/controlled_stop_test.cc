#include "procs/shared/arm/controlled_stop.h"

#include <cmath>

#include <gtest/gtest.h>

namespace ephor::arm {
namespace {

// Position of the servo's cubic Hermite from (q0, v0) at 0 to (q1, 0) at T.
double hermite(double q0, double v0, double q1, double t_end, double t) {
  const double s = t / t_end;
  const double h00 = 2 * s * s * s - 3 * s * s + 1;
  const double h10 = s * s * s - 2 * s * s + s;
  const double h01 = -2 * s * s * s + 3 * s * s;
  return h00 * q0 + h10 * t_end * v0 + h01 * q1;
}

TEST(ControlledStopTest, MovingArmStopsWithinTheDecelerationLimits) {
  const JointLimits limits = Puma560::default_limits();
  Joints q;
  q << 0.1, 0.3, -2.0, 0.2, -0.5, 0.0;
  Joints qd;
  qd << 0.9, -0.5, 0.3, 1.5, 0.0, -1.8;
  const Trajectory stop = controlled_stop(q, qd, limits);
  ASSERT_EQ(stop.points.size(), 1u);
  const TrajectoryPoint& end = stop.points.front();
  EXPECT_GT(end.t_s, 0.0);  // the servo starts from its own state
  EXPECT_TRUE(end.qd.isZero());
  // Sampled like the servo: every joint's acceleration within the limit,
  // velocity never changes sign (no joint turns back).
  const double dt = 1e-3;
  for (int j = 0; j < 6; ++j) {
    double prev_v = qd(j);
    for (double t = dt; t <= end.t_s + 1e-12; t += dt) {
      const double v = (hermite(q(j), qd(j), end.q(j), end.t_s, t) -
                        hermite(q(j), qd(j), end.q(j), end.t_s, t - dt)) /
                       dt;
      EXPECT_LE(std::abs(v - prev_v) / dt, limits.qdd_max(j) * 1.01) << "joint " << j + 1;
      EXPECT_GE(v * qd(j), -1e-9) << "joint " << j + 1 << " turns back";
      prev_v = v;
    }
  }
  // The joint with the largest velocity-to-deceleration ratio sets the time.
  double longest = 0.0;
  for (int j = 0; j < 6; ++j)
    longest = std::max(longest, std::abs(qd(j)) / (0.8 * limits.qdd_max(j)));
  EXPECT_NEAR(end.t_s, longest, 1e-12);
}

TEST(ControlledStopTest, ArmAtRestHoldsWhereItIs) {
  const JointLimits limits = Puma560::default_limits();
  Joints q;
  q << 0.1, 0.3, -2.0, 0.2, -0.5, 0.0;
  const Trajectory stop = controlled_stop(q, Joints::Zero(), limits);
  ASSERT_EQ(stop.points.size(), 1u);
  EXPECT_NEAR(stop.points.front().t_s, 0.05, 1e-12);
  EXPECT_TRUE(stop.points.front().q.isApprox(q));
}

TEST(ControlledStopTest, StopNearAJointLimitEndsInsideTheLimits) {
  const JointLimits limits = Puma560::default_limits();
  Joints q = limits.q_max;
  q(0) -= 0.01;  // joint 1 just short of its limit, still moving toward it
  Joints qd = Joints::Zero();
  qd(0) = 1.0;
  const Trajectory stop = controlled_stop(q, qd, limits);
  EXPECT_TRUE(limits.within(stop.points.front().q));
}

// Found by the fuzz target arm_process: the servo reported 1e300 rad/s (any
// finite joint_state_t is taken) and the stop lasted 6e299 s, infinite as
// joint_trajectory_t's float time.
TEST(ControlledStopTest, AVelocityBeyondTheLimitIsStoppedAsTheLimit) {
  const JointLimits limits = Puma560::default_limits();
  Joints q;
  q << 0.1, 0.3, -2.0, 0.2, -0.5, 0.0;
  Joints qd = Joints::Zero();
  qd(0) = 1e300;
  qd(4) = -50.0;
  const Trajectory stop = controlled_stop(q, qd, limits);
  Joints at_limit = Joints::Zero();
  at_limit(0) = limits.qd_max(0);
  at_limit(4) = -limits.qd_max(4);
  const Trajectory expected = controlled_stop(q, at_limit, limits);
  ASSERT_EQ(stop.points.size(), 1u);
  EXPECT_TRUE(std::isfinite(static_cast<float>(stop.points.front().t_s)));
  EXPECT_DOUBLE_EQ(stop.points.front().t_s, expected.points.front().t_s);
  EXPECT_TRUE(stop.points.front().q.isApprox(expected.points.front().q));
  EXPECT_TRUE(limits.within(stop.points.front().q));
}

}  // namespace
}  // namespace ephor::arm
