#include "common/motion/joint_path_timing.h"

#include <gtest/gtest.h>

namespace ephor::arm {
namespace {

// One joint, no tool-speed constraint: the timing is the trapezoid at 95 % of
// joint 1's limits (1 rad/s, 2 rad/s^2): 1 / 0.95 + 0.95 / 1.9 s.
TEST(JointPathTimingTest, SingleJointMoveIsATrapezoidAtTheJointLimits) {
  const Puma560 arm(100.0);
  Joints a = Joints::Zero(), b = Joints::Zero();
  a << -0.5, 0.5, -2.0, 0.0, 0.5, 0.0;
  b = a;
  b[0] += 1.0;
  const JointPathTiming timing(arm, {a, b}, 1e9);
  EXPECT_NEAR(timing.duration_s(), 1.0 / 0.95 + 0.95 / 1.9, 0.01);
  EXPECT_LT((timing.at(0.0) - a).norm(), 1e-12);
  EXPECT_LT((timing.at(timing.duration_s()) - b).norm(), 1e-12);
  EXPECT_NEAR(timing.at(timing.duration_s() / 2)[0], a[0] + 0.5, 1e-3);  // symmetric profile
}

// The tool-speed cap slows the motion only where the tool sweeps fast.
TEST(JointPathTimingTest, ToolSpeedCapSlowsTheMotion) {
  const Puma560 arm(100.0);
  Joints a, b;
  a << -0.5, 0.3, -1.0, 0.0, 0.5, 0.0;  // arm stretched: joint 1 sweeps the tool fast
  b = a;
  b[0] += 1.0;
  const JointPathTiming free(arm, {a, b}, 1e9);
  const JointPathTiming capped(arm, {a, b}, 100.0);
  EXPECT_GT(capped.duration_s(), free.duration_s() * 2.0);
  double peak = 0.0;
  const double dt = 0.005;
  for (double t = dt; t <= capped.duration_s(); t += dt)
    peak = std::max(peak, (arm.forward(capped.at(t)).translation() -
                           arm.forward(capped.at(t - dt)).translation())
                                  .norm() /
                              dt);
  EXPECT_LE(peak, 100.0);
  EXPECT_GT(peak, 90.0);
}

TEST(JointPathTimingTest, SeveralSegmentsStopAtEachWaypoint) {
  const Puma560 arm(100.0);
  Joints a = Joints::Zero(), b, c;
  a << 0.0, 0.5, -2.0, 0.0, 0.5, 0.0;
  b = a;
  b[1] += 0.3;
  c = b;
  c[2] += 0.3;
  const JointPathTiming timing(arm, {a, b, c}, 1e9);
  const JointPathTiming first(arm, {a, b}, 1e9);
  EXPECT_LT((timing.at(first.duration_s()) - b).norm(), 1e-9);
  EXPECT_LT((timing.at(timing.duration_s()) - c).norm(), 1e-12);
}

}  // namespace
}  // namespace ephor::arm
