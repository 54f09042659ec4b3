#pragma once
// The RAMBO planner's step for laser tagging (paper sections 7-10), as the
// shared arm server can carry it out: the order of the untagged diodes by
// greedy, exhaustive and dynamic programming (TaskOrderer, counting the
// reaching trajectories each computes) and, for the diode being tagged, the
// joint goal that puts the laser on its goal point's predicted pose a short
// lead ahead. Sent again every step, these goals make the tagging joint
// follow the goal trajectory.
//
// What is not the paper's: the shared ephor-arm takes point-to-point goals
// only (no joint trajectory from the planner), so the reaching trajectories
// of sections 8-9 are not what the arm executes; the ordering's cost is the
// section 9 serial-machine heuristic (straight line at a safe tool speed,
// ReachingPlanner::linear_path_duration) plus feasibility (inverse kinematics
// at landing and at the end of the hold), not section 9's scan over T.
//
// Times in s on the wall clock (utime * 1e-6); poses in the base frame, mm.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "common/arm/puma560.h"
#include "common/rambo/joint_trajectory.h"
#include "common/rambo/polynomial_pose_predictor.h"
#include "common/rambo/rambo_cell.h"

namespace ephor::rambo {

// The predictor's fit: a torque-free rigid body with constant momenta, or
// (a target carried by the RM-501, which is no free body) the paper's
// polynomial fits of the six pose coordinates (section 6).
struct FittedMotion {
  double t_ref_s = 0.0;
  Eigen::Vector3d position_mm = Eigen::Vector3d::Zero();  // origin at t_ref
  Eigen::Vector3d velocity_mm_s = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  // target -> base at t_ref
  Eigen::Vector3d body_rates_rad_s = Eigen::Vector3d::Zero();
  Eigen::Vector3d principal_moments = Eigen::Vector3d::Ones();
  // When set, the motion is this polynomial (its times on the same clock as
  // t_ref_s) and the rigid-body fields above are only its state at t_ref_s.
  std::optional<PolynomialMotion> polynomial;
  // Target in base at t_s (the polynomial, else Euler's equations, RK4 in 5 ms steps).
  Eigen::Isometry3d pose(double t_s) const;
  bool finite() const;
};

struct TaggingOptions {
  double lead_s = 0.3;           // goal pose this far ahead of now (the arm's latency)
  double safe_speed_mm_s = 150;  // section 9 heuristic's tool speed
  double settle_s = 0.3;         // added to each straight-line duration
  double hold_margin_s = 1.0;    // hold = required lit duration + this
  double required_s = RamboCell::kRequiredS;
};

struct TaggingStep {
  int task = -1;                      // diode index, -1 = none
  std::optional<arm::Joints> goal_q;  // rad
  std::string status;
  std::vector<int> order;  // diode indices, DP order (empty when not ordered this step)
  std::int64_t greedy_trajectories = 0, exhaustive_trajectories = 0, dp_trajectories = 0;
  double order_total_s = 0.0;
  bool reordered = false;
};

// A reaching trajectory as the arm executes it (sections 8-9): from the
// arm's state onto a goal point's predicted trajectory in the shortest
// duration within the joint limits, then that goal point followed in joint
// space for the hold, so the tagging joint moves with the diode while the
// laser holds on it. Sampled every dt_s from t0_s (wall clock, s).
struct TaggingTrajectory {
  int diode = -1;
  double t0_s = 0.0;
  double dt_s = 0.05;
  std::vector<JointSample> samples;
  double t_land_s = 0.0;    // on the goal point's trajectory (wall clock, s)
  double hold_end_s = 0.0;  // off it again: then a stop at half the acceleration limits
  int durations_tried = 0;  // section 9's columns computed
  bool via_intermediate_goal = false;
  double end_s() const { return t0_s + dt_s * static_cast<double>(samples.size() - 1); }
  // The state at t_s (wall clock, s): linear between samples; before t0_s
  // the first sample, after the end at rest at the last one's position.
  JointSample at(double t_s) const;
};

class TaggingPlanner {
 public:
  TaggingPlanner(const RamboCell& cell, TaggingOptions options = {});

  // tagged[i]: diode i done. current_q: the arm now (rad).
  TaggingStep step(double now_s, const FittedMotion& motion, const std::vector<bool>& tagged,
                   const arm::Joints& current_q);

  int current_task() const { return task_; }

  // The reaching trajectory for `diode` from the arm at (q, qd) at now_s
  // (rad, rad/s; extrapolated at constant velocity), starting at now_s:
  // section 9's scan for the shortest duration within limit_fraction of
  // the joint velocity and acceleration limits, clear of the target's
  // bounding sphere (a safe intermediate goal when the direct one hits it),
  // then the hold (required_s + hold_margin_s) on the goal point's
  // trajectory, then a stop (each joint slowed to rest at half its
  // acceleration limit; the arm's servo would otherwise stop it at once).
  // nullopt, with why, when no duration up to 6 s works.
  // from: the trajectory the arm is executing (section 8: "the present joint
  // trajectory, which may itself be a reaching trajectory started after a
  // previous update"): the new one leaves it at now_s, in position and
  // velocity, instead of the arm's state extrapolated at constant velocity
  // (q, qd are then not used).
  std::optional<TaggingTrajectory> reaching_trajectory(
      int diode, double now_s, const FittedMotion& motion, const arm::Joints& q,
      const arm::Joints& qd, std::string* why, double limit_fraction = 0.8,
      const TaggingTrajectory* from = nullptr) const;

 private:
  std::optional<arm::Joints> goal_joints(int diode, const FittedMotion& m, double t_s,
                                         const arm::Joints& near) const;
  std::optional<arm::Joints> goal_joints_at(int diode, const Eigen::Isometry3d& target_in_base,
                                            const arm::Joints& near) const;
  RamboCell cell_;
  TaggingOptions options_;
  arm::Puma560 arm_;
  int task_ = -1;
  TaggingStep last_order_;
};

}  // namespace ephor::rambo
