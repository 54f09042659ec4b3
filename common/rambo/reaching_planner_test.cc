#include "common/rambo/reaching_planner.h"

#include <cmath>

#include <gtest/gtest.h>

namespace ephor::rambo {
namespace {

constexpr double kDt = 0.01;  // s, the trajectories' common sample step

Joints base_q() { return (Joints() << 0.0, 0.5, -1.0, 0.0, 0.7, 0.0).finished(); }

std::shared_ptr<const SampledJointTrajectory> hold_at(const Joints& q, double seconds = 10.0) {
  return std::make_shared<const SampledJointTrajectory>(SampledJointTrajectory::from_function(
      0.0, kDt, static_cast<int>(seconds / kDt) + 1, [q](double) {
        return JointSample{q, Joints::Zero(), Joints::Zero()};
      }));
}

// Joint 1 moving at constant speed; joint 2 swinging (exact derivatives).
std::shared_ptr<const SampledJointTrajectory> moving_current() {
  return std::make_shared<const SampledJointTrajectory>(
      SampledJointTrajectory::from_function(0.0, kDt, 601, [](double t) {
        JointSample s{base_q(), Joints::Zero(), Joints::Zero()};
        s.q[0] += 0.2 * t;
        s.qd[0] = 0.2;
        return s;
      }));
}
std::shared_ptr<const SampledJointTrajectory> swinging_goal() {
  return std::make_shared<const SampledJointTrajectory>(
      SampledJointTrajectory::from_function(0.0, kDt, 601, [](double t) {
        JointSample s{base_q(), Joints::Zero(), Joints::Zero()};
        s.q[0] = 0.8 + 0.1 * std::sin(1.5 * t);
        s.qd[0] = 0.15 * std::cos(1.5 * t);
        s.qdd[0] = -0.225 * std::sin(1.5 * t);
        s.q[1] += 0.2 * std::sin(t);
        s.qd[1] = 0.2 * std::cos(t);
        s.qdd[1] = -0.2 * std::sin(t);
        return s;
      }));
}

TEST(BlendFraction, ZeroToOneWithFlatEndsAndContinuousSlope) {
  EXPECT_DOUBLE_EQ(blend_fraction(0.0).f, 0.0);
  EXPECT_DOUBLE_EQ(blend_fraction(1.0).f, 1.0);
  EXPECT_DOUBLE_EQ(blend_fraction(0.0).df, 0.0);
  EXPECT_DOUBLE_EQ(blend_fraction(1.0).df, 0.0);
  const BlendValue l = blend_fraction(0.5 - 1e-12), r = blend_fraction(0.5 + 1e-12);
  EXPECT_NEAR(l.f, 0.5, 1e-9);
  EXPECT_NEAR(r.f, 0.5, 1e-9);
  EXPECT_NEAR(l.df, 2.0, 1e-9);  // slope 2/T at T/2 from both sides
  EXPECT_NEAR(r.df, 2.0, 1e-9);
  // As printed in the paper (2 (t/T)^4 first): 1/8 at T/2 against 1/2 just after.
  EXPECT_NEAR(blend_fraction_as_printed(0.5), 0.125, 1e-12);
  EXPECT_NEAR(blend_fraction_as_printed(0.5 + 1e-12), 0.5, 1e-9);
}

void expect_ends_met(ReachingMethod m) {
  auto cur = moving_current();
  auto goal = swinging_goal();
  const double t0 = 0.3, T = 1.2;
  ReachingTrajectory r(m, cur, goal, t0, T);
  const JointSample a = r.at(t0), a0 = cur->at(t0);
  const JointSample b = r.at(t0 + T), b0 = goal->at(t0 + T);
  EXPECT_LT((a.q - a0.q).norm(), 1e-9);
  EXPECT_LT((a.qd - a0.qd).norm(), 1e-9);
  EXPECT_LT((b.q - b0.q).norm(), 1e-9);
  EXPECT_LT((b.qd - b0.qd).norm(), 1e-9);
  // Velocity is the derivative of position along the way (no jumps inside).
  for (double t = t0 + 0.05; t < t0 + T - 0.05; t += 0.1) {
    const Joints num = (r.at(t + 1e-5).q - r.at(t - 1e-5).q) / 2e-5;
    EXPECT_LT((num - r.at(t).qd).norm(), 1e-4) << "t " << t;
  }
}

TEST(ReachingTrajectory, CubicMeetsPositionAndVelocityAtBothEnds) {
  expect_ends_met(ReachingMethod::kCubicSpline);
}
TEST(ReachingTrajectory, BlendMeetsPositionAndVelocityAtBothEnds) {
  expect_ends_met(ReachingMethod::kBlend);
}

// Rest to rest, joint 1 by 1 rad (qd_max 1 rad/s, qdd_max 2 rad/s^2):
// cubic: peak velocity 1.5/T, peak acceleration 6/T^2 -> T >= sqrt(3) = 1.732 s,
// the series 0.1 + 0.05 k gives 1.75 s, and 1.70 s breaks the acceleration limit.
TEST(ReachingPlanner, CubicShortestDurationIsAccelerationBound) {
  ReachingPlanner p(arm::Puma560(100.0), ReachingOptions{});
  Joints qg = base_q();
  qg[0] += 1.0;
  auto cur = hold_at(base_q()), goal = hold_at(qg);
  const ReachingPlan plan = p.shortest(cur, goal, 0.0, nullptr);
  ASSERT_TRUE(plan.feasible()) << plan.reason;
  EXPECT_NEAR(plan.duration_s(), 1.75, 1e-9);
  EXPECT_EQ(plan.durations_tried, 34);  // 0.10, 0.15, ..., 1.75
  const LimitCheck shorter =
      p.check(ReachingTrajectory(ReachingMethod::kCubicSpline, cur, goal, 0.0, 1.70), nullptr);
  EXPECT_EQ(shorter.violation, Violation::kAcceleration);
  EXPECT_EQ(shorter.joint, 0);
  EXPECT_NEAR(std::abs(shorter.value), 6.0 / (1.7 * 1.7), 1e-9);
  // Every sample of the chosen one within limits.
  for (double t = 0.0; t <= 1.75; t += 0.005) {
    const JointSample s = plan.at(t);
    EXPECT_LE(std::abs(s.qd[0]), 1.0 + 1e-9);
    EXPECT_LE(std::abs(s.qdd[0]), 2.0 + 1e-9);
  }
}

// Blend, rest to rest: peak velocity 2/T at T/2, acceleration 4/T^2 ->
// T >= 2 s (velocity bound); 1.95 s breaks the velocity limit.
TEST(ReachingPlanner, BlendShortestDurationIsVelocityBound) {
  ReachingOptions o;
  o.method = ReachingMethod::kBlend;
  ReachingPlanner p(arm::Puma560(100.0), o);
  Joints qg = base_q();
  qg[0] += 1.0;
  auto cur = hold_at(base_q()), goal = hold_at(qg);
  const ReachingPlan plan = p.shortest(cur, goal, 0.0, nullptr);
  ASSERT_TRUE(plan.feasible()) << plan.reason;
  EXPECT_NEAR(plan.duration_s(), 2.0, 1e-9);
  const LimitCheck shorter =
      p.check(ReachingTrajectory(ReachingMethod::kBlend, cur, goal, 0.0, 1.95), nullptr);
  EXPECT_EQ(shorter.violation, Violation::kVelocity);
}

TEST(ReachingPlanner, LimitFractionLengthensTheMove) {
  ReachingOptions o;
  // 0.5 rad/s, 1 rad/s^2: velocity 1.5/T -> T >= 3 s; acceleration 6/T^2 -> T >= 2.449 s.
  o.limit_fraction = 0.5;
  ReachingPlanner p(arm::Puma560(100.0), o);
  Joints qg = base_q();
  qg[0] += 1.0;
  const ReachingPlan plan = p.shortest(hold_at(base_q()), hold_at(qg), 0.0, nullptr);
  ASSERT_TRUE(plan.feasible());
  EXPECT_NEAR(plan.duration_s(), 3.0, 1e-9);
}

TEST(ReachingPlanner, GoalBeyondJointRangeIsRefusedAtEveryDuration) {
  ReachingPlanner p(arm::Puma560(100.0), ReachingOptions{});
  Joints qg = base_q();
  qg[0] = 170.0 * M_PI / 180.0;  // joint 1 stops at 160 deg
  const ReachingPlan plan = p.shortest(hold_at(base_q()), hold_at(qg), 0.0, nullptr);
  EXPECT_FALSE(plan.feasible());
  EXPECT_EQ(plan.last_refusal.violation, Violation::kPosition);
  EXPECT_NE(plan.reason.find("joint position limit of joint 1"), std::string::npos) << plan.reason;
}

// The target sits where the tool passes when only the waist turns: the
// direct move hits it, the plan goes round through an intermediate goal.
TEST(ReachingPlanner, IntermediateGoalAvoidsTheTarget) {
  const arm::Puma560 arm(100.0);
  ReachingPlanner p(arm, ReachingOptions{});
  Joints qa = base_q(), qb = base_q(), qm = base_q();
  qa[0] = -0.6;
  qb[0] = 0.6;
  const Eigen::Vector3d centre = arm.forward(qm).translation();
  TargetSphere target{[centre](double) { return centre; }, 80.0};
  const Eigen::Isometry3d goal_pose = arm.forward(qb);
  auto cur = hold_at(qa, 20.0);

  // Direct: refused for the collision.
  auto goal_j = hold_at(qb, 20.0);
  const ReachingPlan direct = p.shortest(cur, goal_j, 0.0, &target);
  EXPECT_FALSE(direct.feasible());
  EXPECT_EQ(direct.last_refusal.violation, Violation::kCollision);

  const ReachingPlan plan = p.plan(
      cur, [&](double) { return goal_pose; }, 0.0, 15.0, &target);
  ASSERT_TRUE(plan.feasible()) << plan.reason;
  EXPECT_EQ(plan.status, ReachingStatus::kViaIntermediateGoal);
  ASSERT_EQ(plan.legs.size(), 2u);
  for (const auto& leg : plan.legs) EXPECT_TRUE(p.check(leg, &target).ok());
  // Lands on the goal at rest.
  const JointSample end = plan.at(plan.t_land_s);
  EXPECT_LT((arm.forward(end.q).translation() - goal_pose.translation()).norm(), 1e-3);
  EXPECT_LT(end.qd.norm(), 1e-6);
  // Position and velocity continuous where the legs meet.
  const double tm = plan.legs[0].t_land_s();
  EXPECT_LT((plan.legs[0].at(tm).q - plan.legs[1].at(tm).q).norm(), 1e-9);
  EXPECT_LT((plan.legs[0].at(tm).qd - plan.legs[1].at(tm).qd).norm(), 1e-9);
}

TEST(ReachingPlanner, GoalOutOfReachSaysSo) {
  ReachingPlanner p(arm::Puma560(100.0), ReachingOptions{});
  const Eigen::Isometry3d far(Eigen::Translation3d(5000.0, 0.0, 0.0));
  const ReachingPlan plan = p.plan(
      hold_at(base_q()), [&](double) { return far; }, 0.0, 5.0, nullptr);
  EXPECT_EQ(plan.status, ReachingStatus::kGoalUnreachable);
  EXPECT_NE(plan.reason.find("out of reach"), std::string::npos) << plan.reason;
}

TEST(ReachingPlanner, BadOptionsAreRejected) {
  ReachingOptions o;
  o.duration_step_s = 0.0;
  EXPECT_THROW(ReachingPlanner(arm::Puma560(), o), std::invalid_argument);
  o = ReachingOptions{};
  o.limit_fraction = std::nan("");
  EXPECT_THROW(ReachingPlanner(arm::Puma560(), o), std::invalid_argument);
}

TEST(SampledJointTrajectory, DifferencesRecoverAParabola) {
  std::vector<Joints> q;
  for (int k = 0; k < 20; ++k) {
    const double t = 0.1 * k;
    q.push_back(Joints::Constant(1.0 + 2.0 * t + 1.5 * t * t));
  }
  const auto tr = SampledJointTrajectory::from_positions(0.0, 0.1, q);
  for (double t : {0.0, 0.55, 1.9}) {
    const JointSample s = tr.at(t);
    EXPECT_NEAR(s.q[0], 1.0 + 2.0 * t + 1.5 * t * t, 1e-9);
    EXPECT_NEAR(s.qd[0], 2.0 + 3.0 * t, 1e-9);
    EXPECT_NEAR(s.qdd[0], 3.0, 1e-9);
  }
  EXPECT_THROW(SampledJointTrajectory(0.0, 0.0, {JointSample{}}), std::invalid_argument);
}

}  // namespace
}  // namespace ephor::rambo
