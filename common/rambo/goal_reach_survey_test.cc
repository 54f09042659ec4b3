// survey_goal_reach on hand-checked motions: a target at rest facing the
// arm, the same turned away, and one turning from away to towards.
#include "common/rambo/goal_reach_survey.h"

#include <gtest/gtest.h>

namespace ephor::rambo {
namespace {

Eigen::Isometry3d facing_the_arm() {
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.translation() = Eigen::Vector3d(900.0, 0.0, 100.0);  // as RamboCell::draw_motion, no tilt
  return p;
}

TEST(GoalReachSurvey, AtRestFacingTheArmEveryGoalIsInReachThroughout) {
  const RamboCell cell = RamboCell::make(4);
  GoalReachSurveyOptions o;
  o.duration_s = 10.0;
  o.step_s = 1.0;
  const auto r = survey_goal_reach(
      cell, [](double) { return facing_the_arm(); }, o);
  ASSERT_EQ(r.size(), 4u);
  for (const DiodeReach& d : r) {
    EXPECT_EQ(d.samples, 11) << d.name;
    EXPECT_EQ(d.reachable, 11) << d.name;
    EXPECT_DOUBLE_EQ(d.first_reachable_s, 0.0) << d.name;
    EXPECT_DOUBLE_EQ(d.longest_window_s, 10.0) << d.name;
    EXPECT_DOUBLE_EQ(d.reachable_fraction(), 1.0) << d.name;
    EXPECT_DOUBLE_EQ(d.in_reach_from_start_s, 11.0) << d.name;  // never out: past the span
  }
}

TEST(GoalReachSurvey, TurnedAwayTheFrontGoalIsBehindTheTargetAndNeverInReach) {
  const RamboCell cell = RamboCell::make(1);  // "front": 200 mm out along -x
  Eigen::Isometry3d away = facing_the_arm();
  away.linear() = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  GoalReachSurveyOptions o;
  o.duration_s = 4.0;
  const auto r = survey_goal_reach(
      cell, [&](double) { return away; }, o);
  ASSERT_EQ(r.size(), 1u);
  EXPECT_EQ(r[0].reachable, 0);
  EXPECT_DOUBLE_EQ(r[0].first_reachable_s, -1.0);
  EXPECT_DOUBLE_EQ(r[0].longest_window_s, 0.0);
  EXPECT_DOUBLE_EQ(r[0].in_reach_from_start_s, 0.0);
}

TEST(GoalReachSurvey, ATargetTurningTowardsTheArmComesIntoReachOnceTheHoldIsToo) {
  const RamboCell cell = RamboCell::make(1);
  // Turned away (180 deg about z) until 5 s, facing the arm from 5 s on: with
  // a 2 s hold the first time reachable at t and t + 2 s is 5 s.
  auto target_at = [](double t) {
    Eigen::Isometry3d p = facing_the_arm();
    if (t < 5.0) p.linear() = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    return p;
  };
  GoalReachSurveyOptions o;
  o.duration_s = 10.0;
  o.step_s = 0.5;
  o.hold_s = 2.0;
  const auto r = survey_goal_reach(cell, target_at, o);
  EXPECT_DOUBLE_EQ(r[0].first_reachable_s, 5.0);
  EXPECT_EQ(r[0].reachable, 11);  // 5.0 .. 10.0
  EXPECT_DOUBLE_EQ(r[0].longest_window_s, 5.0);
}

TEST(GoalReachSurvey, AGoalLeavingReachWithinTheHoldDoesNotCount) {
  const RamboCell cell = RamboCell::make(1);
  // Facing the arm until 5 s, turned away from 5 s on: with a 2 s hold the
  // last time that counts is 2.5 s (0, 0.5, .. 2.5: 6 samples; at 3 s the
  // hold would end at 5 s, turned away); with none, 4.5 s.
  auto target_at = [](double t) {
    Eigen::Isometry3d p = facing_the_arm();
    if (t >= 5.0) p.linear() = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    return p;
  };
  GoalReachSurveyOptions o;
  o.duration_s = 10.0;
  o.step_s = 0.5;
  o.hold_s = 2.0;
  EXPECT_EQ(survey_goal_reach(cell, target_at, o)[0].reachable, 6);
  EXPECT_DOUBLE_EQ(survey_goal_reach(cell, target_at, o)[0].in_reach_from_start_s, 3.0);
  EXPECT_DOUBLE_EQ(survey_goal_reach(cell, target_at, o)[0].longest_window_s, 2.5);
  o.hold_s = 0.0;
  EXPECT_EQ(survey_goal_reach(cell, target_at, o)[0].reachable, 10);
}

TEST(GoalReachSurvey, BadOptionsAreRefused) {
  const RamboCell cell = RamboCell::make(1);
  GoalReachSurveyOptions o;
  o.step_s = 0.0;
  EXPECT_THROW(survey_goal_reach(
                   cell, [](double) { return facing_the_arm(); }, o),
               std::invalid_argument);
  o = {};
  o.hold_s = -1.0;
  EXPECT_THROW(survey_goal_reach(
                   cell, [](double) { return facing_the_arm(); }, o),
               std::invalid_argument);
}

}  // namespace
}  // namespace ephor::rambo
