#include "common/motion/speed_scaler.h"

#include <algorithm>

#include <gtest/gtest.h>

#include "common/motion/trapezoid_profile.h"

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

// The servo of ephor-sim follows the cubic Hermite curve through the points
// and their velocities, stepping every 4 ms, and faults when the reference's
// acceleration exceeds 1.5 x the limit. A short move with a triangular
// profile whose 10 ms finite differences sit at the limit has a cubic whose
// acceleration spikes to 1.8 x the limit at the points; the servo's steps
// caught 1.5-1.65 x of such spikes on the full system (servo faults). The
// scaler now keeps the cubic within 1.45 x.
TEST(SpeedScalerTest, ShortTriangularMoveStaysWithinTheServosAccelerationCheck) {
  const Puma560 arm(100.0);
  ScalingConfig config;
  config.max_tool_speed_mm_s = 1e9;
  const SpeedScaler scaler(arm, config);
  Joints start = Joints::Zero();
  start[1] = 0.5;
  start[2] = -2.0;
  // Joint 3 turns 0.04 rad at 1.9 rad/s^2 (the limit is 2): a triangle of
  // 0.29 s whose peak falls between two 10 ms points.
  const TrapezoidProfile profile(0.04, 10.0, 1.9);
  const TimedPath path = [&](double t, const Joints&, std::string*) -> std::optional<Joints> {
    Joints q = start;
    q[2] += profile.position(t);
    return q;
  };
  const ScaledTrajectory s = scaler.scale(path, profile.duration_s(), start);
  ASSERT_TRUE(s.ok) << s.reason;
  const auto& pts = s.trajectory.points;
  const auto reference = [&](double t) {
    size_t i = 0;
    while (i + 2 < pts.size() && pts[i + 1].t_s <= t) ++i;
    const double h = pts[i + 1].t_s - pts[i].t_s;
    const double u = std::clamp((t - pts[i].t_s) / h, 0.0, 1.0);
    const double u2 = u * u, u3 = u2 * u;
    return ((2 * u3 - 3 * u2 + 1) * pts[i].q + (u3 - 2 * u2 + u) * h * pts[i].qd +
            (-2 * u3 + 3 * u2) * pts[i + 1].q + (u3 - u2) * h * pts[i + 1].qd)
        .eval();
  };
  const double dt = 0.004;
  double worst = 0.0;
  Joints v_prev = Joints::Zero();
  for (double t = 0.0; t + dt <= s.trajectory.duration_s(); t += dt) {
    const Joints v = (reference(t + dt) - reference(t)) / dt;
    if (t > 0.0) {
      worst = std::max(
          worst,
          ((v - v_prev) / dt).array().abs().cwiseQuotient(arm.limits().qdd_max.array()).maxCoeff());
    }
    v_prev = v;
  }
  // Below the servo's 1.5 x with a margin for its 4 ms steps (1.43 x before the check).
  EXPECT_LT(worst, 1.4);
  // The cubic's own acceleration at the ends of each segment, which the
  // servo's 4 ms steps catch depending on their phase: within 1.45 x the
  // limit (1.8 x before the scaler checked it).
  double ends = 0.0;
  for (size_t i = 0; i + 1 < pts.size(); ++i) {
    const double h = pts[i + 1].t_s - pts[i].t_s;
    const Joints dq = pts[i + 1].q - pts[i].q;
    const Joints a0 = (6.0 * dq / h - 4.0 * pts[i].qd - 2.0 * pts[i + 1].qd) / h;
    const Joints a1 = (-6.0 * dq / h + 2.0 * pts[i].qd + 4.0 * pts[i + 1].qd) / h;
    ends = std::max({ends, a0.array().abs().cwiseQuotient(arm.limits().qdd_max.array()).maxCoeff(),
                     a1.array().abs().cwiseQuotient(arm.limits().qdd_max.array()).maxCoeff()});
  }
  EXPECT_LE(ends, 1.45);
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
