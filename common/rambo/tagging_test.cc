// RamboCell, DiodeIndicator and TaggingPlanner on hand-checked cases.
#include <gtest/gtest.h>

#include "common/config/repo_paths.h"
#include "common/rambo/diode_indicator.h"
#include "common/rambo/rambo_cell.h"
#include "common/rambo/tagging_planner.h"
#include "common/rambo/target_model_file.h"

#include <chrono>
#include <cstdio>

namespace ephor::rambo {
namespace {

TEST(RamboCell, GoalsPutTheBeamIntoTheLensesAndAreReachableAtRest) {
  const RamboCell cell = RamboCell::make(4);
  const arm::Puma560 arm(cell.tool_length_mm);
  TumblingMotion m = cell.draw_motion(1, 2.0, 1.0);
  m.pose0.linear().setIdentity();  // as built, before the seed's tilt
  DiodeIndicator ind(cell.diodes, 5.0, 12.0, 1.0);
  for (int i = 0; i < 4; ++i) {
    const Eigen::Isometry3d goal = m.pose0 * cell.goal_in_target(i);
    EXPECT_TRUE(arm.nearest_inverse(goal, cell.start_joints).has_value()) << "diode " << i;
    const DiodeReading r = ind.read(i, m.pose0, goal.translation(), goal.linear().col(2));
    EXPECT_TRUE(r.lit) << i;
    EXPECT_NEAR(r.beam_angle_deg, 0.0, 1e-6);
    EXPECT_NEAR(r.beam_offset_mm, 0.0, 1e-6);
  }
  // The start pose lights no diode: tagging is the planner's work.
  const Eigen::Isometry3d start = arm.forward(cell.start_joints);
  for (int i = 0; i < 4; ++i)
    EXPECT_FALSE(ind.read(i, m.pose0, start.translation(), start.linear().col(2)).lit) << i;
  EXPECT_THROW(RamboCell::make(0), std::invalid_argument);
  EXPECT_THROW(RamboCell::make(5), std::invalid_argument);
}

TEST(DiodeIndicator, TagsAfterTheRequiredUnbrokenDuration) {
  const RamboCell cell = RamboCell::make(1);
  DiodeIndicator ind(cell.diodes, 5.0, 12.0, 1.0);
  const Eigen::Isometry3d target = Eigen::Isometry3d::Identity();
  const Eigen::Isometry3d on = cell.goal_in_target(0);
  const Eigen::Vector3d dir = on.linear().col(2);
  // 6 deg off the axis: not lit.
  const Eigen::Vector3d tilted =
      Eigen::AngleAxisd(6.0 * M_PI / 180.0, Eigen::Vector3d::UnitZ()) * dir;
  EXPECT_FALSE(ind.read(0, target, on.translation(), tilted).lit);
  // 15 mm beside the lens: not lit.
  EXPECT_FALSE(ind.read(0, target, on.translation() + Eigen::Vector3d(0, 15, 0), dir).lit);
  // Beam pointing away: not lit.
  EXPECT_FALSE(ind.read(0, target, on.translation(), -dir).lit);
  for (int k = 0; k <= 5; ++k) ind.step(0.1 * k, target, on.translation(), dir);
  EXPECT_EQ(ind.lit_diode(), 0);
  EXPECT_FALSE(ind.tagged(0));
  ind.step(0.6, target, on.translation(), tilted);  // broken
  EXPECT_EQ(ind.lit_diode(), -1);
  for (int k = 7; k <= 16; ++k) ind.step(0.1 * k, target, on.translation(), dir);
  EXPECT_FALSE(ind.tagged(0));
  ind.step(1.75, target, on.translation(), dir);
  EXPECT_TRUE(ind.tagged(0));
  EXPECT_NEAR(ind.tagged_at_s(0), 1.75, 1e-9);
  // NaN beam: no beam, no crash.
  ind.step(1.8, target, Eigen::Vector3d::Constant(std::nan("")), dir);
  EXPECT_EQ(ind.lit_diode(), -1);
  // The demo's next round: untagged, and tagged again only after a full
  // second lit from the reset, even with the beam held on it throughout.
  for (int k = 19; k <= 20; ++k) ind.step(0.1 * k, target, on.translation(), dir);
  ind.reset_tags(2.0);
  EXPECT_FALSE(ind.tagged(0));
  EXPECT_EQ(ind.tagged_count(), 0);
  ind.step(2.9, target, on.translation(), dir);
  EXPECT_FALSE(ind.tagged(0));
  ind.step(3.05, target, on.translation(), dir);
  EXPECT_TRUE(ind.tagged(0));
}

TEST(TaggingPlanner, OrdersTheOpenDiodesAndAimsAtTheFirst) {
  const RamboCell cell = RamboCell::make(4);
  TumblingMotion m = cell.draw_motion(3, 2.0, 1.0);
  m.pose0.linear().setIdentity();  // every diode within reach (the "left" one barely)
  m.body_rates_rad_s = Eigen::Vector3d(0.0, 0.0, 0.01);
  FittedMotion f;
  f.t_ref_s = 100.0;
  f.position_mm = m.pose0.translation();
  f.velocity_mm_s = m.velocity_mm_s;
  f.orientation = Eigen::Quaterniond(m.pose0.linear());
  f.body_rates_rad_s = m.body_rates_rad_s;
  f.principal_moments = cell.principal_moments;
  TaggingPlanner planner(cell);
  const TaggingStep s = planner.step(100.0, f, {false, true, false, false}, cell.start_joints);
  ASSERT_TRUE(s.reordered);
  ASSERT_EQ(s.order.size(), 3u);
  EXPECT_TRUE(std::find(s.order.begin(), s.order.end(), 1) == s.order.end());
  EXPECT_EQ(s.exhaustive_trajectories, 15);  // 3 tasks, all feasible
  EXPECT_EQ(s.dp_trajectories, 15);
  EXPECT_EQ(s.greedy_trajectories, 6);
  ASSERT_TRUE(s.goal_q.has_value());
  EXPECT_EQ(s.task, s.order.front());
  // The goal puts the beam into that diode's lens at now + lead.
  const arm::Puma560 arm(cell.tool_length_mm);
  const Eigen::Isometry3d tool = arm.forward(*s.goal_q);
  DiodeIndicator ind(cell.diodes, 5.0, 12.0, 1.0);
  EXPECT_TRUE(ind.read(s.task, f.pose(100.3), tool.translation(), tool.linear().col(2)).lit);
  // The same task is kept while it is open; a bad prediction gives no goal.
  EXPECT_FALSE(planner.step(100.2, f, {false, true, false, false}, *s.goal_q).reordered);
  FittedMotion bad = f;
  bad.position_mm.x() = std::nan("");
  EXPECT_FALSE(planner.step(100.4, bad, {false, false, false, false}, *s.goal_q).goal_q);
}

// The model file's eight diodes, all within reach of a slow tumble: every
// method orders all of them, DP's order takes exhaustive's time, and the
// counts are the formulas' (common/rambo/README.md).
TEST(TaggingPlanner, OrdersEightDiodesOfTheModelFile) {
  const RamboCell cell = RamboCell::make(
      load_target_model_file((repo_dir() / "deploy/rambo/target.pbtxt").string()), 8);
  TumblingMotion m = cell.draw_motion(3, 2.0, 1.0);
  FittedMotion f;
  f.t_ref_s = 100.0;
  f.position_mm = m.pose0.translation();
  f.orientation = Eigen::Quaterniond::Identity();
  f.body_rates_rad_s = Eigen::Vector3d(0.0, 0.0, 0.002);
  f.principal_moments = cell.principal_moments;
  TaggingPlanner planner(cell);
  const auto t0 = std::chrono::steady_clock::now();
  const TaggingStep s = planner.step(100.0, f, std::vector<bool>(8, false), cell.start_joints);
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  std::printf("8 diodes ordered in %.0f ms: greedy %ld, exhaustive %ld, DP %ld, %.2f s\n", ms,
              static_cast<long>(s.greedy_trajectories),
              static_cast<long>(s.exhaustive_trajectories), static_cast<long>(s.dp_trajectories),
              s.order_total_s);
  ASSERT_TRUE(s.reordered);
  EXPECT_EQ(s.order.size(), 8u);
  EXPECT_EQ(s.greedy_trajectories, 36);
  EXPECT_EQ(s.exhaustive_trajectories, 109600);
  EXPECT_EQ(s.dp_trajectories, 3592);
  EXPECT_TRUE(s.goal_q.has_value());
}

// The reaching trajectory the arm executes (sections 8-9): it starts where
// the arm is, stays within the share of the joint limits it was planned for
// (checked as the arm checks it: speeds, and accelerations from the speeds
// of neighbouring samples), lands on the goal point's trajectory and then
// holds the beam in the diode's lens for the hold.
TEST(TaggingPlanner, ReachingTrajectoryStartsAtTheArmAndHoldsTheBeamOnTheDiode) {
  const RamboCell cell = RamboCell::make(4);
  TumblingMotion m = cell.draw_motion(3, 2.0, 1.0);
  m.pose0.linear().setIdentity();
  FittedMotion f;
  f.t_ref_s = 100.0;
  f.position_mm = m.pose0.translation();
  f.velocity_mm_s = m.velocity_mm_s;
  f.orientation = Eigen::Quaterniond::Identity();
  f.body_rates_rad_s = Eigen::Vector3d(0.0, 0.0, 0.03);  // 1.7 deg/s
  f.principal_moments = cell.principal_moments;
  const TaggingPlanner planner(cell);
  const arm::Puma560 arm(cell.tool_length_mm);
  const arm::JointLimits& lim = arm.limits();
  arm::Joints qd = arm::Joints::Zero();
  qd[0] = 0.1;  // the arm still turning a little
  std::string why;
  const auto t = planner.reaching_trajectory(0, 100.0, f, cell.start_joints, qd, &why);
  ASSERT_TRUE(t.has_value()) << why;
  ASSERT_GE(t->samples.size(), 10u);
  EXPECT_LT((t->samples.front().q - cell.start_joints).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT((t->samples.front().qd - qd).cwiseAbs().maxCoeff(), 1e-6);
  for (std::size_t k = 0; k < t->samples.size(); ++k) {
    const auto& s = t->samples[k];
    for (int j = 0; j < 6; ++j) {
      EXPECT_LE(std::abs(s.qd[j]), 0.8 * lim.qd_max[j] + 1e-6) << "sample " << k << " joint " << j;
      if (k > 0) {
        const double qdd = (s.qd[j] - t->samples[k - 1].qd[j]) / t->dt_s;
        EXPECT_LE(std::abs(qdd), lim.qdd_max[j]) << "sample " << k << " joint " << j;
      }
    }
  }
  // From landing to the end (the hold: required 1 s + 1 s margin) the beam
  // is in the lens.
  EXPECT_NEAR(t->hold_end_s - t->t_land_s, 2.0, t->dt_s + 1e-9);
  // Then it stops: at rest at the end.
  EXPECT_LT(t->samples.back().qd.cwiseAbs().maxCoeff(), 1e-9);
  DiodeIndicator ind(cell.diodes, 5.0, 12.0, 1.0);
  int lit = 0, after_landing = 0;
  for (std::size_t k = 0; k < t->samples.size(); ++k) {
    const double ts = t->t0_s + t->dt_s * static_cast<double>(k);
    if (ts < t->t_land_s + 1e-9 || ts > t->hold_end_s + 1e-9) continue;
    ++after_landing;
    const Eigen::Isometry3d tool = arm.forward(t->samples[k].q);
    lit += ind.read(0, f.pose(ts), tool.translation(), tool.linear().col(2)).lit ? 1 : 0;
  }
  EXPECT_GE(after_landing, 39);
  EXPECT_EQ(lit, after_landing);
  // A bad diode or arm state: no trajectory, with the reason.
  arm::Joints nan_q = cell.start_joints;
  nan_q[2] = std::nan("");
  EXPECT_FALSE(planner.reaching_trajectory(0, 100.0, f, nan_q, qd, &why));
  EXPECT_FALSE(why.empty());
}

// Section 8's re-planning: when the prediction updates while the arm is on
// a reaching trajectory, the new one leaves that trajectory (not the arm's
// state extrapolated at constant velocity) in position and velocity, and
// lands on the updated goal trajectory with the beam in the lens.
TEST(TaggingPlanner, ReplanningLeavesTheRunningTrajectoryAndFollowsTheNewPrediction) {
  const RamboCell cell = RamboCell::make(4);
  TumblingMotion m = cell.draw_motion(3, 2.0, 1.0);
  FittedMotion f;
  f.t_ref_s = 100.0;
  f.position_mm = m.pose0.translation();
  f.velocity_mm_s = m.velocity_mm_s;
  f.orientation = Eigen::Quaterniond::Identity();
  f.body_rates_rad_s = Eigen::Vector3d(0.0, 0.0, 0.03);
  f.principal_moments = cell.principal_moments;
  const TaggingPlanner planner(cell);
  const arm::Puma560 arm(cell.tool_length_mm);
  std::string why;
  const auto first =
      planner.reaching_trajectory(0, 100.0, f, cell.start_joints, arm::Joints::Zero(), &why);
  ASSERT_TRUE(first.has_value()) << why;
  // Halfway to landing the prediction moves: 20 mm aside, turning faster.
  const double t1 = 0.5 * (first->t0_s + first->t_land_s);
  ASSERT_GT(first->t_land_s - t1, 0.1);
  FittedMotion g = f;
  g.position_mm += Eigen::Vector3d(0.0, 20.0, 0.0);
  g.body_rates_rad_s = Eigen::Vector3d(0.0, 0.01, 0.035);
  const JointSample there = first->at(t1);
  ASSERT_GT(there.qd.cwiseAbs().maxCoeff(), 1e-3);  // moving
  // The arm's state is given wrong on purpose: with `from` it is not used.
  const auto second = planner.reaching_trajectory(0, t1, g, cell.start_joints, arm::Joints::Zero(),
                                                  &why, 0.8, &*first);
  ASSERT_TRUE(second.has_value()) << why;
  EXPECT_LT((second->samples.front().q - there.q).cwiseAbs().maxCoeff(), 1e-6);
  EXPECT_LT((second->samples.front().qd - there.qd).cwiseAbs().maxCoeff(), 1e-6);
  // Within the arm's step limits from sample to sample, and on the new
  // goal point while holding.
  const arm::JointLimits& lim = arm.limits();
  for (std::size_t k = 1; k < second->samples.size(); ++k)
    for (int j = 0; j < 6; ++j)
      EXPECT_LE(std::abs(second->samples[k].qd[j] - second->samples[k - 1].qd[j]) / second->dt_s,
                lim.qdd_max[j])
          << "sample " << k << " joint " << j;
  DiodeIndicator ind(cell.diodes, 5.0, 12.0, 1.0);
  int lit = 0, holding = 0;
  for (std::size_t k = 0; k < second->samples.size(); ++k) {
    const double ts = second->t0_s + second->dt_s * static_cast<double>(k);
    if (ts < second->t_land_s + 1e-9 || ts > second->hold_end_s + 1e-9) continue;
    ++holding;
    const Eigen::Isometry3d tool = arm.forward(second->samples[k].q);
    lit += ind.read(0, g.pose(ts), tool.translation(), tool.linear().col(2)).lit ? 1 : 0;
  }
  EXPECT_GE(holding, 39);
  EXPECT_EQ(lit, holding);
  // The running trajectory between samples and beyond its end (at rest).
  const JointSample end = first->at(first->end_s() + 1.0);
  EXPECT_LT((end.q - first->samples.back().q).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_EQ(end.qd.cwiseAbs().maxCoeff(), 0.0);
}

}  // namespace
}  // namespace ephor::rambo
