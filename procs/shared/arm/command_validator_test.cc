#include "procs/shared/arm/command_validator.h"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "common/arm/arm_workcell.h"

namespace ephor::arm {
namespace {

class CommandValidatorTest : public ::testing::Test {
 protected:
  geometry::Workcell cell_;
  geometry::OverheadCamera camera_;
  CommandValidator validator_{calibration::FieldCalibration::from_camera(camera_, cell_), cell_};
  Joints current_ = park_joints(cell_);

  // A valid command: the image of a field point in the elevation plane.
  ArmCommand command_at(double x, double y, int plane = kPlaneElevation) const {
    const double z = plane == kPlaneObject ? cell_.object_plane_z_mm : cell_.elevation_plane_z_mm;
    const Eigen::Vector2d uv = camera_.project(x, y, z);
    ArmCommand c;
    c.seq = 1;
    c.plane = plane;
    c.u_px = uv.x();
    c.v_px = uv.y();
    c.theta_rad = 0.3;
    c.max_speed_mm_s = 200.0;
    return c;
  }
  void expect_rejected(const ArmCommand& c, const std::string& words) const {
    const Validation v = validator_.validate(c, current_);
    EXPECT_FALSE(v.ok);
    EXPECT_NE(v.reason.find(words), std::string::npos) << "reason: " << v.reason;
  }
};

TEST_F(CommandValidatorTest, ValidCommandBecomesAToolDownPoseAtTheImagedPoint) {
  for (int plane : {kPlaneElevation, kPlaneObject}) {
    const Validation v = validator_.validate(command_at(1000.0, 200.0, plane), current_);
    ASSERT_TRUE(v.ok) << v.reason;
    EXPECT_NEAR(v.target.tip_mm.x(), 1000.0, 0.01);
    EXPECT_NEAR(v.target.tip_mm.y(), 200.0, 0.01);
    const ToolInField t = tool_in_field(cell_, v.target.goal_q);
    EXPECT_LT((t.tip_mm - v.target.tip_mm).norm(), 1e-6);
    EXPECT_NEAR(t.tilt_rad, 0.0, 1e-6);
    // theta is measured from +u towards +v (v down), F's y is up: the sign flips.
    EXPECT_NEAR(v.target.theta_field_rad, -0.3, 1e-6);
    EXPECT_DOUBLE_EQ(v.target.speed_mm_s, 200.0);
  }
}

TEST_F(CommandValidatorTest, ZeroSpeedMeansTheDefaultCap) {
  ArmCommand c = command_at(1000.0, 200.0);
  c.max_speed_mm_s = 0.0;
  const Validation v = validator_.validate(c, current_);
  ASSERT_TRUE(v.ok) << v.reason;
  EXPECT_DOUBLE_EQ(v.target.speed_mm_s, 300.0);
}

TEST_F(CommandValidatorTest, RejectsNonFiniteNumbers) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  ArmCommand c = command_at(1000.0, 200.0);
  c.u_px = nan;
  expect_rejected(c, "not finite");
  c = command_at(1000.0, 200.0);
  c.v_px = -inf;
  expect_rejected(c, "not finite");
  c = command_at(1000.0, 200.0);
  c.theta_rad = inf;
  expect_rejected(c, "theta");
  c = command_at(1000.0, 200.0);
  c.max_speed_mm_s = nan;
  expect_rejected(c, "speed");
}

TEST_F(CommandValidatorTest, RejectsUnknownPlaneAndBadSpeed) {
  ArmCommand c = command_at(1000.0, 200.0);
  c.plane = 7;
  expect_rejected(c, "unknown plane 7");
  c = command_at(1000.0, 200.0);
  c.plane = -1;
  expect_rejected(c, "unknown plane");
  c = command_at(1000.0, 200.0);
  c.max_speed_mm_s = -5.0;
  expect_rejected(c, "negative");
  c = command_at(1000.0, 200.0);
  c.max_speed_mm_s = 301.0;
  expect_rejected(c, "above the arm's cap of 300");
  // Found by the fuzz target arm_process: 1e-40 mm/s planned a motion of
  // 5e44 s, its times infinite as floats.
  c = command_at(1000.0, 200.0);
  c.max_speed_mm_s = 1e-40;
  expect_rejected(c, "below the arm's minimum of 10 mm/s");
  c.max_speed_mm_s = 10.0;
  EXPECT_TRUE(validator_.validate(c, current_).ok);
}

TEST_F(CommandValidatorTest, RejectsTargetsOutsideTheImageOrTheField) {
  ArmCommand c = command_at(1000.0, 200.0);
  c.u_px = 512.0;
  expect_rejected(c, "outside the 512 x 482 image");
  c = command_at(1000.0, 200.0);
  c.v_px = -1.0;
  expect_rejected(c, "outside the 512 x 482 image");
  // The image shows more than the field: a point 40 mm beyond the right edge.
  c = command_at(cell_.field_length_mm + 40.0, 200.0, kPlaneObject);
  ASSERT_LT(c.u_px, 511.0);
  expect_rejected(c, "outside the 1219 x 914 mm field");
}

TEST_F(CommandValidatorTest, RejectsUnreachableTargets) {
  // Above the column: inside the ring the PUMA cannot reach with the tool down.
  expect_rejected(command_at(cell_.base_x_mm + 30.0, cell_.base_y_mm),
                  "out of the PUMA 560's reach");
  expect_rejected(command_at(cell_.base_x_mm + 250.0, cell_.base_y_mm),
                  "out of the PUMA 560's reach");
}

TEST_F(CommandValidatorTest, RejectsWhenTheCurrentJointsAreUnknown) {
  Joints unknown = Joints::Constant(std::numeric_limits<double>::quiet_NaN());
  const Validation v = validator_.validate(command_at(1000.0, 200.0), unknown);
  EXPECT_FALSE(v.ok);
  EXPECT_NE(v.reason.find("current joints"), std::string::npos) << v.reason;
}

}  // namespace
}  // namespace ephor::arm

namespace ephor::arm {
namespace {

// Pose and joint goals (arm_goal_t.KIND_POSE / KIND_JOINTS): what the
// catching system and others send; no image or calibration involved.
class PoseGoalTest : public CommandValidatorTest {
 protected:
  ArmCommand pose_at(double x, double y, double z) const {
    ArmCommand c;
    c.kind = kKindPose;
    c.position_mm = Eigen::Vector3d(x, y, z);
    c.theta_rad = 0.2;
    return c;
  }
};

TEST_F(PoseGoalTest, APoseGoalPutsTheToolTipThereTheToolDown) {
  const Validation v = validator_.validate(pose_at(1000.0, 200.0, 120.0), current_);
  ASSERT_TRUE(v.ok) << v.reason;
  const ToolInField t = tool_in_field(cell_, v.target.goal_q);
  EXPECT_LT((t.tip_mm - Eigen::Vector3d(1000.0, 200.0, 120.0)).norm(), 1e-6);
  EXPECT_NEAR(t.tilt_rad, 0.0, 1e-6);
  EXPECT_NEAR(t.theta_rad, 0.2, 1e-6);
}

TEST_F(PoseGoalTest, BadPoseGoalsAreRefusedNamingTheProblem) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  expect_rejected(pose_at(nan, 200.0, 120.0), "not finite");
  expect_rejected(pose_at(cell_.field_length_mm + 50.0, 200.0, 120.0), "outside the work cell");
  expect_rejected(pose_at(1000.0, 200.0, -10.0), "above the table");
  expect_rejected(pose_at(1210.0, 900.0, 790.0),
                  "out of the PUMA 560's reach");  // the far corner, high
  ArmCommand unknown = pose_at(1000.0, 200.0, 120.0);
  unknown.kind = 7;
  expect_rejected(unknown, "unknown goal kind 7");
}

TEST_F(PoseGoalTest, JointGoalsAreCheckedAgainstTheJointLimits) {
  ArmCommand c;
  c.kind = kKindJoints;
  c.joints = current_;
  const Validation v = validator_.validate(c, current_);
  ASSERT_TRUE(v.ok) << v.reason;
  EXPECT_LT((v.target.goal_q - current_).norm(), 1e-12);
  c.joints[0] = 3.5;  // joint 1 stops at +-160 deg (2.79 rad)
  expect_rejected(c, "joint 1 target 3.500 rad is outside");
}

// Joint trajectories (arm_goal_t.KIND_TRAJECTORY): executed as given, so
// every point is checked against the PUMA's limits (qd_max 1 rad/s and
// qdd_max 2 rad/s^2 on joints 1-3).
class TrajectoryGoalTest : public CommandValidatorTest {
 protected:
  // Joint 1 from the current joints by `rad`, rest to rest, as a cubic
  // q(s) = 3 s^2 - 2 s^3 over duration_s, sampled every 10 ms: peak speed
  // 1.5 rad / T, peak acceleration 6 rad / T^2.
  ArmCommand cubic(double rad, double duration_s) const {
    ArmCommand c;
    c.kind = kKindTrajectory;
    const int n = static_cast<int>(std::lround(duration_s / 0.01));
    for (int k = 0; k <= n; ++k) {
      const double s = static_cast<double>(k) / n;
      TrajectoryPoint p;
      p.t_s = s * duration_s;
      p.q = current_;
      p.q[0] += rad * (3 * s * s - 2 * s * s * s);
      p.qd[0] = rad * (6 * s - 6 * s * s) / duration_s;
      c.trajectory.points.push_back(p);
    }
    return c;
  }
};

TEST_F(TrajectoryGoalTest, ATrajectoryWithinTheLimitsIsAcceptedAsGiven) {
  // 0.5 rad in 2 s: 0.375 rad/s and 0.75 rad/s^2 at most.
  const ArmCommand c = cubic(0.5, 2.0);
  const Validation v = validator_.validate(c, current_);
  ASSERT_TRUE(v.ok) << v.reason;
  EXPECT_LT((v.target.goal_q - c.trajectory.points.back().q).norm(), 1e-12);
}

TEST_F(TrajectoryGoalTest, LimitsBrokenAnywhereAreRefusedNamingPointJointAndValue) {
  // 0.5 rad in 0.5 s: 1.5 rad/s peak (limit 1 rad/s) and 12 rad/s^2 at the
  // start (limit 2): the acceleration at the first step is met first.
  expect_rejected(cubic(0.5, 0.5), "trajectory point 1 (t 0.010 s): joint 1 acceleration");
  {
    ArmCommand c = cubic(0.5, 2.0);
    c.trajectory.points[100].qd[1] = 1.2;  // joint 2, 1.2 rad/s at t = 1 s
    expect_rejected(c, "joint 2 speed 1.200 rad/s is above its limit 1.000 rad/s");
  }
  {
    ArmCommand c = cubic(0.5, 2.0);
    c.trajectory.points[50].q[0] = 3.5;  // joint 1 stops at 2.79 rad
    expect_rejected(c, "trajectory point 50 (t 0.500 s): joint 1 at 3.500 rad is outside");
  }
  {
    ArmCommand c = cubic(0.5, 2.0);
    for (auto& p : c.trajectory.points) p.q[2] += 0.2;  // not where the arm is
    expect_rejected(c, "trajectory starts 0.200 rad from the arm's current joints");
  }
  {
    ArmCommand c = cubic(0.5, 2.0);
    c.trajectory.points[10].t_s = c.trajectory.points[9].t_s;
    expect_rejected(c, "at point 10 does not increase");
  }
  {
    ArmCommand c = cubic(0.5, 2.0);
    c.trajectory.points[3].qd[4] = std::numeric_limits<double>::quiet_NaN();
    expect_rejected(c, "trajectory point 3 is not finite");
  }
  {
    // Found by the fuzz target arm_process: at rest at both points, every
    // point within the limits, but 0.3 rad in 0.1 s between them (the servo
    // faults on the mean velocity).
    ArmCommand c;
    c.kind = kKindTrajectory;
    TrajectoryPoint p;
    p.q = current_;
    c.trajectory.points.push_back(p);
    p.t_s = 0.1;
    p.q[0] += 0.3;
    c.trajectory.points.push_back(p);
    expect_rejected(c, "trajectory points 0-1 (t 0.000-0.100 s): joint 1 moves at 3.000 rad/s");
  }
  ArmCommand one = cubic(0.5, 2.0);
  one.trajectory.points.resize(1);
  expect_rejected(one, "trajectory has 1 point(s)");
}

}  // namespace
}  // namespace ephor::arm
