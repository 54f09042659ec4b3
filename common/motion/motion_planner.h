#pragma once
// MotionPlanner: from the arm's current joints to a tool pose (base frame,
// mm), as the paper's manipulation process does it (section 3.6):
//
//  1. the goal joints are the inverse-kinematics solution nearest the current
//     joints;
//  2. the preferred motion is the straight line of the tool in Cartesian space
//     at the requested speed (trapezoid in path length; the tool turns about
//     its axis on the way), checked by inverse kinematics every few mm: each
//     sample within joint limits, on the same branch (no jump), clear of the
//     table and the pedestal, the tool never lower than the lower end;
//  3. if that line is not feasible, OMPL finds a joint-space path between the
//     same joints (JointSpacePlanner), each straight joint segment a
//     synchronised trapezoid;
//  4. SpeedScaler samples the motion at the servo rate, checks every joint's
//     velocity and acceleration and the tool speed, and slows the whole motion
//     down when one would exceed its limit.
//
// Pure code, no LCM. Thread-compatible (const methods, no shared state apart
// from OMPL's global RNG).

#include <optional>
#include <string>

#include <Eigen/Geometry>

#include "common/arm/puma560.h"
#include "common/geometry/workcell.h"
#include "common/motion/arm_collision_checker.h"
#include "common/motion/joint_space_planner.h"
#include "common/motion/speed_scaler.h"
#include "common/motion/trajectory.h"

namespace ephor::arm {

struct MotionPlannerConfig {
  double max_speed_mm_s = 300.0;         // default and cap of the tool speed, mm/s
  double cartesian_accel_mm_s2 = 800.0;  // tool acceleration along the line, mm/s^2
  // Turning the tool about its axis counts as this much travel per rad when
  // timing a Cartesian move (a pure turn would otherwise take no time), mm/rad.
  double turn_equivalent_mm_per_rad = 100.0;
  double check_step_mm = 2.0;         // Cartesian feasibility check spacing, mm
  double check_step_rad = 0.02;       // ... and in tool rotation, rad
  double max_joint_step_rad = 0.08;   // a larger jump between checks = branch change/singularity
  double tip_height_margin_mm = 5.0;  // the tool may dip this far below the lower end, mm
  ScalingConfig scaling;
  JointPlannerConfig joint_planner;
  CollisionConfig collision;
};

enum class MotionKind { kStay, kCartesian, kJointSpace };
const char* to_string(MotionKind kind);

struct MotionPlan {
  bool ok = false;
  std::string reason;  // why no motion (when !ok)
  MotionKind kind = MotionKind::kStay;
  std::string cartesian_rejected;  // why the straight line was not used ("" if it was)
  Joints goal_q = Joints::Zero();  // rad
  Trajectory trajectory;
  double requested_speed_mm_s = 0.0;
  double speed_scale = 1.0;  // the paper's scale-down factor: 1 / time stretch (<= 1)
  double peak_tool_speed_mm_s = 0.0;
  double velocity_ratio = 0.0;      // max |qd| / qd_max along the plan
  double acceleration_ratio = 0.0;  // max |qdd| / qdd_max
  JointPath joint_path;             // when kind == kJointSpace
};

class MotionPlanner {
 public:
  MotionPlanner(const geometry::Workcell& cell, MotionPlannerConfig config = {});

  // speed_mm_s: requested tool speed, 0 = the default cap; clamped to the cap.
  MotionPlan plan(const Joints& start, const Eigen::Isometry3d& goal_in_base,
                  double speed_mm_s) const;

  // nullopt when the straight Cartesian line from FK(start) to goal is
  // feasible and ends at goal_q; else why not.
  std::optional<std::string> check_cartesian(const Joints& start,
                                             const Eigen::Isometry3d& goal_in_base,
                                             const Joints& goal_q, double min_tip_z_mm) const;

  const Puma560& arm() const { return arm_; }
  const ArmCollisionChecker& collisions() const { return collisions_; }
  const MotionPlannerConfig& config() const { return config_; }

 private:
  MotionPlan plan_cartesian(const Joints& start, const Eigen::Isometry3d& goal_in_base,
                            const Joints& goal_q, double speed_mm_s) const;
  MotionPlan plan_joint_space(const Joints& start, const Joints& goal_q, double speed_mm_s,
                              double min_tip_z_mm) const;

  geometry::Workcell cell_;
  MotionPlannerConfig config_;
  Puma560 arm_;
  ArmCollisionChecker collisions_;
  JointSpacePlanner joint_planner_;
};

}  // namespace ephor::arm
