#include "common/shepherd/calibrate/joint_move.h"

#include <cmath>

#include <gtest/gtest.h>

namespace ephor::calibrate {
namespace {

TEST(JointMove, StaysWithinTheFractionOfTheLimitsAndEndsAtRest) {
  const auto limits = arm::Puma560::default_limits();
  arm::Joints a, b;
  a << 0.1, 0.2, -0.3, 0.0, 0.5, 1.0;
  b << -1.2, 1.0, -0.5, 0.4, -0.2, -2.0;
  const auto p = JointMove::plan(a, b, limits, 0.5, 0.05);
  ASSERT_GE(p.t_s.size(), 3u);
  EXPECT_EQ(p.t_s.front(), 0.0);
  EXPECT_TRUE(p.q.front().isApprox(a));
  EXPECT_TRUE(p.q.back().isApprox(b));
  EXPECT_TRUE(p.qd.back().isZero());
  EXPECT_TRUE(p.qd.front().isZero());
  for (size_t k = 1; k < p.t_s.size(); ++k) {
    const double dt = p.t_s[k] - p.t_s[k - 1];
    ASSERT_GT(dt, 0.0);
    EXPECT_LE(dt, 0.05 + 1e-12);
    for (int j = 0; j < 6; ++j) {
      EXPECT_LE(std::abs(p.qd[k](j)), 0.5 * limits.qd_max(j) + 1e-9) << "joint " << j;
      EXPECT_LE(std::abs(p.q[k](j) - p.q[k - 1](j)) / dt, 0.5 * limits.qd_max(j) + 1e-9);
      EXPECT_LE(std::abs(p.qd[k](j) - p.qd[k - 1](j)) / dt, 0.5 * limits.qdd_max(j) + 1e-9);
    }
  }
  // Joint 6 (3 rad at 1 rad/s) limits the duration: 1.5 * 3 / 1 = 4.5 s.
  EXPECT_NEAR(p.duration_s(), 4.5, 1e-9);
}

TEST(JointMove, RefusesBadInput) {
  const auto limits = arm::Puma560::default_limits();
  arm::Joints a = arm::Joints::Zero(), bad = a;
  bad(1) = 10.0;
  EXPECT_THROW(JointMove::plan(a, bad, limits), std::invalid_argument);
  bad(1) = NAN;
  EXPECT_THROW(JointMove::plan(a, bad, limits), std::invalid_argument);
  EXPECT_THROW(JointMove::plan(a, a, limits, 0.0), std::invalid_argument);
  EXPECT_NO_THROW(JointMove::plan(a, a, limits));  // a move of nothing is a short hold
}

}  // namespace
}  // namespace ephor::calibrate
