#pragma once
// CommandValidator: decides whether an arm command may move the arm, and
// turns a valid one into a tool pose. Bad commands are refused with a reason
// that names the problem and the value (the ack carries it back to the
// planner); nothing about a refused command reaches the servo.
//
// Checks for an image target (kKindImage), in order: every number finite;
// plane known; speed 0 (the cap) or within [min_speed_mm_s, the cap]; target inside the image;
// target (via the calibration of its plane) inside the field; tool-down pose reachable by the PUMA
// within its joint limits and clear of the table and pedestal. A pose target (kKindPose) skips the
// image and calibration: its tip must lie inside the work cell's area, between the table and
// max_tip_height_mm, and pass the same reach and collision checks. A joint
// target (kKindJoints) must be within the joint limits and collision-free.
// A joint trajectory (kKindTrajectory) is executed as given, so the arm
// checks all of it: at least two points, times from 0 and increasing, every
// number finite, its first point at the current joints (within
// trajectory_start_tolerance_rad), every point within the joint position
// and velocity limits and collision-free, the mean velocity between
// neighbouring points within the velocity limits (the servo's check) and the
// velocity change between them within the acceleration limits; a refusal
// names the point, the joint and the value.
//
// Image orientation theta (rad from +u towards +v) becomes an orientation in
// F through the calibration's linear part (the paper's section 5: "a vector
// from the origin of the image ... the corresponding world vector").

#include <string>

#include <Eigen/Geometry>

#include "common/arm/puma560.h"
#include "common/calibration/field_calibration.h"
#include "common/geometry/workcell.h"
#include "common/motion/arm_collision_checker.h"
#include "procs/shared/arm/arm_command.h"

namespace ephor::arm {

struct ValidatorConfig {
  int image_width_px = 512;
  int image_height_px = 482;
  double max_speed_mm_s = 300.0;  // the cap; also the speed of a command that asks for 0
  // The slowest tool speed a command may ask for (0 asks for the cap), mm/s: a
  // speed of 1e-40 mm/s planned a motion of 5e44 s whose times are infinite as
  // floats (fuzz target arm_process).
  double min_speed_mm_s = 10.0;
  double max_tip_height_mm = 800.0;              // kKindPose: highest tool tip above the table, mm
  double trajectory_start_tolerance_rad = 0.05;  // kKindTrajectory: first point vs current
};

// A command that passed: where the tool goes.
struct ArmTarget {
  calibration::Plane plane = calibration::Plane::kElevation;
  Eigen::Vector3d tip_mm = Eigen::Vector3d::Zero();  // tool tip in F, mm
  double theta_field_rad = 0.0;                      // manipulator orientation in F, rad
  Eigen::Isometry3d pose_in_base = Eigen::Isometry3d::Identity();  // tool pose, base frame, mm
  Joints goal_q = Joints::Zero();  // IK solution nearest the current joints
  double speed_mm_s = 0.0;         // tool speed to use, mm/s (> 0)
};

struct Validation {
  bool ok = false;
  std::string reason;  // when !ok
  ArmTarget target;
};

class CommandValidator {
 public:
  CommandValidator(calibration::FieldCalibration calibration, const geometry::Workcell& cell,
                   ValidatorConfig config = {});

  // `current`: the arm's joints now (to choose the nearest IK solution).
  Validation validate(const ArmCommand& cmd, const Joints& current) const;

  const calibration::FieldCalibration& calibration() const { return calibration_; }
  const ValidatorConfig& config() const { return config_; }

 private:
  Validation validate_image(const ArmCommand& cmd, const Joints& current) const;
  Validation validate_pose(const ArmCommand& cmd, const Joints& current) const;
  Validation validate_joints(const ArmCommand& cmd) const;
  Validation validate_trajectory(const ArmCommand& cmd, const Joints& current) const;
  // Speed checks shared by every kind; empty when fine.
  std::string speed_problem(double max_speed_mm_s) const;
  // IK nearest `current` and the collision check for a tool-down target in F.
  Validation reach(const Eigen::Vector3d& tip_mm, double theta_field_rad, const Joints& current,
                   double max_speed_mm_s) const;

  calibration::FieldCalibration calibration_;
  geometry::Workcell cell_;
  ValidatorConfig config_;
  Puma560 arm_;
  ArmCollisionChecker collisions_;
};

}  // namespace ephor::arm
