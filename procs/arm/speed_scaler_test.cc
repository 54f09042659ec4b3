#include "procs/arm/speed_scaler.h"

#include <gtest/gtest.h>

#include "procs/arm/trapezoid_profile.h"

namespace ephor::arm {
namespace {

TEST(TrapezoidProfileTest, TrapezoidAndTriangle) {
  const TrapezoidProfile trap(100.0, 50.0, 100.0);  // ramps 0.5 s and 12.5 mm each
  EXPECT_NEAR(trap.duration_s(), 0.5 + 0.5 + 75.0 / 50.0, 1e-12);
  EXPECT_NEAR(trap.position(0.5), 12.5, 1e-12);
  EXPECT_NEAR(trap.position(trap.duration_s()), 100.0, 1e-12);
  EXPECT_NEAR(trap.speed(1.0), 50.0, 1e-12);
  const TrapezoidProfile tri(1.0, 50.0, 100.0);  // never reaches 50
  EXPECT_NEAR(tri.peak_speed(), 10.0, 1e-12);
  EXPECT_NEAR(tri.duration_s(), 0.2, 1e-12);
  EXPECT_NEAR(tri.position(0.1), 0.5, 1e-12);
  EXPECT_THROW(TrapezoidProfile(1.0, 0.0, 1.0), std::invalid_argument);
}

// Joint 1 asked to turn 2 rad in 1 s with a linear profile (2 rad/s, its limit
// is 1 rad/s): the scaler slows the whole motion down to within the limits.
TEST(SpeedScalerTest, StretchesAMotionThatWouldExceedAJointLimit) {
  const Puma560 arm(100.0);
  ScalingConfig config;
  config.max_tool_speed_mm_s = 1e9;  // test the joint limits only
  const SpeedScaler scaler(arm, config);
  Joints start = Joints::Zero();
  start[1] = 0.5;
  start[2] = -2.0;
  const TrapezoidProfile profile(2.0, 2.0, 20.0);
  const TimedPath path = [&](double t, const Joints&, std::string*) -> std::optional<Joints> {
    Joints q = start;
    q[0] += profile.position(t) - 1.0;
    return q;
  };
  const ScaledTrajectory s =
      scaler.scale(path, profile.duration_s(), Joints(start - Joints::Unit(0)));
  ASSERT_TRUE(s.ok) << s.reason;
  EXPECT_GT(s.stretch, 2.0);
  EXPECT_LE(s.velocity_ratio, 1.0);
  EXPECT_LE(s.acceleration_ratio, 1.0);
  EXPECT_NEAR(s.trajectory.points.back().q[0], start[0] + 1.0, 1e-12);
  EXPECT_NEAR(s.trajectory.duration_s(), profile.duration_s() * s.stretch, 1e-9);
}

TEST(SpeedScalerTest, RefusesAPathThatCannotBeFollowed) {
  const Puma560 arm;
  const SpeedScaler scaler(arm);
  const TimedPath broken = [](double t, const Joints& prev,
                              std::string* why) -> std::optional<Joints> {
    if (t > 0.5) {
      *why = "no IK here";
      return std::nullopt;
    }
    return prev;
  };
  const ScaledTrajectory s = scaler.scale(broken, 1.0, Joints::Zero());
  EXPECT_FALSE(s.ok);
  EXPECT_EQ(s.reason, "no IK here");
}

}  // namespace
}  // namespace ephor::arm
