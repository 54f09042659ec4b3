#pragma once
// PumaArmMotion: the kinematic stand-in's arm (KinematicField) as ephor-arm
// moves it: each goal is planned by ephor-arm's MotionPlanner (straight
// tool line when feasible, OMPL joint-space path otherwise, speed scaling)
// from the arm's current joints and followed along its trajectory. A
// planner on the stand-in then pays for configuration changes (12-15 s),
// detours around the column and slowed-down moves as on the full system,
// at a thousand times real time.
//
// Not checked here: ephor-arm's command validation (field and reach
// limits), comm's latency (KinematicFieldConfig::goal_latency_s has it) and
// the servo layer's tracking error.

#include <array>

#include "common/arm/puma560.h"
#include "common/geometry/workcell.h"
#include "common/motion/motion_planner.h"
#include "common/motion/trajectory.h"
#include "procs/shepherd/planner/kinematic_field.h"

namespace ephor::planner {

class PumaArmMotion : public ArmMotion {
 public:
  // The arm starts at park_joints(cell). speed_mm_s: the tool speed asked
  // of every move (ephor-arm caps it at its own maximum).
  explicit PumaArmMotion(const geometry::Workcell& cell, double speed_mm_s = 300.0);

  bool start(double x_mm, double y_mm, double z_mm, double theta_rad) override;
  bool step(double dt_s) override;
  std::array<double, 3> tool_mm() const override;
  JointAngles joints() const override;

  // Moves planned so far, and how many of them were joint-space paths.
  int moves() const { return moves_; }
  int joint_space_moves() const { return joint_space_moves_; }
  double joint_space_time_s() const { return joint_space_time_s_; }
  double move_time_s() const { return move_time_s_; }  // of every move planned, s

 private:
  geometry::Workcell cell_;
  double speed_mm_s_;
  arm::MotionPlanner planner_;
  arm::Joints q_;
  arm::Trajectory trajectory_;
  double t_s_ = 0.0;
  int moves_ = 0;
  int joint_space_moves_ = 0;
  double joint_space_time_s_ = 0.0;
  double move_time_s_ = 0.0;
};

}  // namespace ephor::planner
