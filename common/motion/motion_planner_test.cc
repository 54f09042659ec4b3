#include "common/motion/motion_planner.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "common/arm/arm_workcell.h"

namespace ephor::arm {
namespace {

// Joint velocity/acceleration ratios of a trajectory computed here from its
// points alone (independent of SpeedScaler's bookkeeping).
struct Ratios {
  double velocity = 0.0;
  double acceleration = 0.0;
  double tool_speed_mm_s = 0.0;
};

Ratios measure(const Trajectory& traj, const Puma560& arm) {
  Ratios r;
  const auto& p = traj.points;
  for (std::size_t j = 1; j < p.size(); ++j) {
    const double dt = p[j].t_s - p[j - 1].t_s;
    EXPECT_GT(dt, 0.0);
    const Joints v = (p[j].q - p[j - 1].q) / dt;
    r.velocity = std::max(r.velocity, (v.array().abs() / arm.limits().qd_max.array()).maxCoeff());
    r.tool_speed_mm_s = std::max(
        r.tool_speed_mm_s,
        (arm.forward(p[j].q).translation() - arm.forward(p[j - 1].q).translation()).norm() / dt);
    if (j + 1 < p.size()) {
      const double dt2 = p[j + 1].t_s - p[j].t_s;
      const Joints a = ((p[j + 1].q - p[j].q) / dt2 - v) / (0.5 * (dt + dt2));
      r.acceleration =
          std::max(r.acceleration, (a.array().abs() / arm.limits().qdd_max.array()).maxCoeff());
    }
  }
  return r;
}

class MotionPlannerTest : public ::testing::Test {
 protected:
  geometry::Workcell cell_;
  MotionPlanner planner_{cell_};

  Joints joints_at(double x, double y, double z, double theta = 0.0) const {
    const auto q =
        planner_.arm().nearest_inverse(tool_down_pose(cell_, x, y, z, theta), reference_joints());
    EXPECT_TRUE(q.has_value()) << x << ", " << y << ", " << z;
    return q.value_or(Joints::Zero());
  }
  void expect_ends_at(const MotionPlan& plan, const Eigen::Isometry3d& goal) const {
    ASSERT_FALSE(plan.trajectory.empty());
    const Joints& last = plan.trajectory.points.back().q;
    EXPECT_LT((last - plan.goal_q).cwiseAbs().maxCoeff(), 1e-9);
    EXPECT_LT((planner_.arm().forward(last).translation() - goal.translation()).norm(), 1e-6);
    EXPECT_TRUE(plan.trajectory.points.back().qd.isZero());
    EXPECT_TRUE(plan.trajectory.points.front().qd.isZero());
  }
};

TEST_F(MotionPlannerTest, StraightLineInElevationPlaneAtTheRequestedSpeed) {
  const Joints start = joints_at(1000.0, 150.0, cell_.elevation_plane_z_mm);
  const Eigen::Isometry3d goal =
      tool_down_pose(cell_, 1000.0, 750.0, cell_.elevation_plane_z_mm, 0.5);
  const MotionPlan plan = planner_.plan(start, goal, 200.0);
  ASSERT_TRUE(plan.ok) << plan.reason;
  EXPECT_EQ(plan.kind, MotionKind::kCartesian) << plan.cartesian_rejected;
  expect_ends_at(plan, goal);
  const Ratios r = measure(plan.trajectory, planner_.arm());
  EXPECT_LE(r.velocity, 1.0);
  EXPECT_LE(r.acceleration, 1.0);
  EXPECT_LE(r.tool_speed_mm_s, 200.0 * 1.001);
  EXPECT_GT(r.tool_speed_mm_s, 190.0);      // it does reach the requested speed on a 600 mm line
  EXPECT_DOUBLE_EQ(plan.speed_scale, 1.0);  // far from the column no joint is near its limit
  // The tool stays on the line: every sample at the elevation plane height.
  for (const auto& p : plan.trajectory.points)
    EXPECT_NEAR(tool_in_field(cell_, p.q).tip_mm.z(), cell_.elevation_plane_z_mm, 1e-6);
}

// The paper's check: near the column joint 1 must turn fast for a tangential
// tool move (about v / r rad/s); at 300 mm/s that exceeds 1 rad/s, so the
// whole motion is slowed down until no joint is over its limit.
TEST_F(MotionPlannerTest, ScalesTheWholeMotionDownWhenAJointWouldExceedItsLimit) {
  const double z = cell_.object_plane_z_mm;
  const double r = 190.0;  // mm from the column
  const Joints start = joints_at(cell_.base_x_mm + r, cell_.base_y_mm - 100.0, z);
  const Eigen::Isometry3d goal =
      tool_down_pose(cell_, cell_.base_x_mm + r, cell_.base_y_mm + 100.0, z, 0.0);
  const MotionPlan fast = planner_.plan(start, goal, 300.0);
  ASSERT_TRUE(fast.ok) << fast.reason;
  EXPECT_EQ(fast.kind, MotionKind::kCartesian) << fast.cartesian_rejected;
  EXPECT_LT(fast.speed_scale, 0.9);
  expect_ends_at(fast, goal);
  const Ratios rf = measure(fast.trajectory, planner_.arm());
  EXPECT_LE(rf.velocity, 1.0);
  EXPECT_GT(rf.velocity, 0.9);  // scaled just enough, not more
  EXPECT_LE(rf.acceleration, 1.0);
  EXPECT_LT(rf.tool_speed_mm_s, 300.0 * fast.speed_scale * 1.01);

  // Slower requests need less scaling (near the column the acceleration
  // limit of joint 1 still binds at the default tool acceleration).
  const MotionPlan slow = planner_.plan(start, goal, 50.0);
  ASSERT_TRUE(slow.ok) << slow.reason;
  EXPECT_GT(slow.speed_scale, fast.speed_scale);
  EXPECT_GT(slow.trajectory.duration_s(), fast.trajectory.duration_s());
}

TEST_F(MotionPlannerTest, RandomMovesOverTheFieldRespectJointLimitsAndEndAtTheTarget) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> ux(0.0, cell_.field_length_mm),
      uy(0.0, cell_.field_width_mm), ut(-3.0, 3.0);
  Joints q = park_joints(cell_);
  int planned = 0, joint_space = 0;
  for (int n = 0; n < 12; ++n) {
    const double x = ux(rng), y = uy(rng);
    const double z = n % 2 ? cell_.object_plane_z_mm : cell_.elevation_plane_z_mm;
    if (distance_from_column_mm(cell_, x, y) < 360.0) continue;
    const Eigen::Isometry3d goal = tool_down_pose(cell_, x, y, z, ut(rng));
    const MotionPlan plan = planner_.plan(q, goal, 300.0);
    if (!plan.ok) {
      ADD_FAILURE() << "(" << x << ", " << y << ", " << z << "): " << plan.reason;
      continue;
    }
    ++planned;
    joint_space += plan.kind == MotionKind::kJointSpace;
    expect_ends_at(plan, goal);
    const Ratios r = measure(plan.trajectory, planner_.arm());
    EXPECT_LE(r.velocity, 1.0);
    EXPECT_LE(r.acceleration, 1.0);
    EXPECT_LE(r.tool_speed_mm_s, 300.0 * 1.001);
    for (const auto& p : plan.trajectory.points)
      EXPECT_TRUE(planner_.arm().limits().within(p.q, 1e-9));
    q = plan.goal_q;
  }
  EXPECT_GE(planned, 6);
  RecordProperty("joint_space_moves", joint_space);
}

// Crossing the field in the elevation plane: the straight line passes over the
// column, where the elevation plane is out of reach, so OMPL finds a
// joint-space path; the tool never dips below the plane and nothing collides.
TEST_F(MotionPlannerTest, FallsBackToOmplWhenTheStraightLineIsInfeasible) {
  const double z = cell_.elevation_plane_z_mm;
  const Joints start = joints_at(150.0, 457.0, z);
  const Eigen::Isometry3d goal = tool_down_pose(cell_, 1069.0, 457.0, z, 0.0);
  const MotionPlan plan = planner_.plan(start, goal, 300.0);
  ASSERT_TRUE(plan.ok) << plan.reason;
  EXPECT_EQ(plan.kind, MotionKind::kJointSpace);
  EXPECT_FALSE(plan.cartesian_rejected.empty());
  EXPECT_EQ(plan.joint_path.status, JointPathStatus::kFound);
  expect_ends_at(plan, goal);
  const Ratios r = measure(plan.trajectory, planner_.arm());
  EXPECT_LE(r.velocity, 1.0);
  EXPECT_LE(r.acceleration, 1.0);
  EXPECT_LE(r.tool_speed_mm_s, 300.0 * 1.001);
  for (const auto& p : plan.trajectory.points) {
    EXPECT_TRUE(planner_.collisions().clear(p.q, z - 5.0 - 1e-6))
        << *planner_.collisions().collision(p.q, z - 5.0 - 1e-6);
  }
}

TEST_F(MotionPlannerTest, UnreachableOrNonFiniteGoalIsRefusedWithAReason) {
  const Joints start = park_joints(cell_);
  const MotionPlan centre = planner_.plan(
      start, tool_down_pose(cell_, cell_.base_x_mm, cell_.base_y_mm, 30.0, 0.0), 100.0);
  EXPECT_FALSE(centre.ok);
  EXPECT_NE(centre.reason.find("out of reach"), std::string::npos) << centre.reason;
  Eigen::Isometry3d nan_goal = tool_down_pose(cell_, 100.0, 100.0, 30.0, 0.0);
  nan_goal.translation().x() = std::nan("");
  EXPECT_FALSE(planner_.plan(start, nan_goal, 100.0).ok);
  EXPECT_FALSE(planner_.plan(start, tool_down_pose(cell_, 1000.0, 100.0, 200.0, 0.0), -1.0).ok);
}

TEST_F(MotionPlannerTest, NoMotionNeededGivesASinglePoint) {
  const Joints start = park_joints(cell_);
  const MotionPlan plan = planner_.plan(start, planner_.arm().forward(start), 300.0);
  ASSERT_TRUE(plan.ok) << plan.reason;
  EXPECT_EQ(plan.kind, MotionKind::kStay);
  ASSERT_EQ(plan.trajectory.points.size(), 1u);
  EXPECT_DOUBLE_EQ(plan.trajectory.duration_s(), 0.0);
}

TEST(JointSpacePlannerTest, ReportsTimeoutAsAStatusNotAnException) {
  const JointLimits limits = Puma560::default_limits();
  JointPlannerConfig config;
  config.time_budget_s = 0.05;
  const JointSpacePlanner planner(limits, config);
  Joints start = Joints::Zero(), goal = Joints::Zero();
  start[0] = -1.0;
  goal[0] = 1.0;
  // A wall at q1 = 0 that no path can cross.
  const auto valid = [](const Joints& q) { return std::abs(q[0]) > 0.1; };
  const JointPath path = planner.plan(start, goal, valid);
  EXPECT_EQ(path.status, JointPathStatus::kTimedOut);
  EXPECT_FALSE(path.reason.empty());
  EXPECT_EQ(planner.plan(Joints::Zero(), goal, valid).status, JointPathStatus::kInvalidStart);
  EXPECT_EQ(planner.plan(start, Joints::Zero(), valid).status, JointPathStatus::kInvalidGoal);
}

}  // namespace
}  // namespace ephor::arm
