#include "common/sphere/world/capture_judge.h"

#include <gtest/gtest.h>

namespace ephor::sphere {
namespace {

SphereTrajectory line(Eigen::Vector3d p0, Eigen::Vector3d v) {
  SphereTrajectory s;
  s.position_at_t0_m = p0;
  s.velocity_m_s = v;
  return s;
}

TEST(CaptureJudge, CapturesASlowCentredSphereWhenItReachesOneMetre) {
  CaptureJudge j;
  // From 1.05 m at 1 cm/s: reaches 1 m at t = 5 s, offset 0.5 cm + 5 s * 0.1 cm/s = 1.0 cm.
  const auto s = line({0.005, 0.0, 1.05}, {0.001, 0.0, -0.01});
  EXPECT_FALSE(j.judge(s, 0.0, 4.9).has_value());
  const auto v = j.judge(s, 4.9, 5.4);
  ASSERT_TRUE(v.has_value());
  EXPECT_TRUE(v->captured) << v->text;
  EXPECT_NEAR(v->t_s, 5.0, 1e-9);
  EXPECT_NEAR(v->offset_m, 0.010, 1e-9);
  EXPECT_NEAR(v->speed_m_s, std::hypot(0.001, 0.01), 1e-12);
}

TEST(CaptureJudge, TooFastOrOffTheAxisIsNotCaptured) {
  CaptureJudge j;
  const auto fast = j.judge(line({0, 0, 1.1}, {0, 0, -0.021}), 0.0, 10.0);
  ASSERT_TRUE(fast.has_value());
  EXPECT_FALSE(fast->captured);
  EXPECT_NE(fast->text.find("too fast"), std::string::npos) << fast->text;
  const auto off = j.judge(line({0.015, 0.015, 1.1}, {0, 0, -0.01}), 0.0, 20.0);
  ASSERT_TRUE(off.has_value());
  EXPECT_FALSE(off->captured);  // offset 2.12 cm
  EXPECT_NE(off->text.find("off the axis"), std::string::npos) << off->text;
}

TEST(CaptureJudge, NeverReachedWhenMovingAway) {
  CaptureJudge j;
  EXPECT_FALSE(j.judge(line({0, 0, 2}, {0, 0, 0.01}), 0.0, 100.0).has_value());
  const CaptureVerdict g = j.give_up(line({0, 0, 2}, {0, 0, 0.01}), 100.0);
  EXPECT_FALSE(g.captured);
  EXPECT_NE(g.text.find("gave up"), std::string::npos);
}

}  // namespace
}  // namespace ephor::sphere
