#pragma once
// The shortest reaching trajectory within the arm's limits (RAMBO paper,
// section 9) and the safe intermediate goal when the direct one would hit
// the target or a limit.
//
// Section 9's method: compute the reaching trajectory for a series of
// durations T (the CM-2's columns), sample each at the trajectories' common
// time step, find its largest positions, velocities and accelerations, and
// keep the smallest T that breaks no limit. Feasibility is not monotone in T
// (a longer blend can swing a joint further), so this is a scan, not a
// bisection; we scan T upward and stop at the first feasible one, which is
// the same choice as evaluating every column and taking the smallest.
// Derivatives are exact (analytic, from the samples' velocities and
// accelerations), where the CM-2 estimated them from neighbouring cells.
//
// The target is a sphere moving with the target (centre trajectory in the
// base frame, mm); the tool tip and the flange must stay outside it.

#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "common/arm/puma560.h"
#include "common/rambo/reaching_trajectory.h"

namespace ephor::rambo {

struct TargetSphere {
  std::function<Eigen::Vector3d(double)> centre_mm;  // base frame, mm, at time t (s)
  double radius_mm = 0.0;
};

struct ReachingOptions {
  ReachingMethod method = ReachingMethod::kCubicSpline;
  double duration_min_s = 0.1;    // first T of the series, s
  double duration_step_s = 0.05;  // increment between columns, s
  double duration_max_s = 6.0;    // last T, s
  double limit_fraction = 1.0;    // of qd_max and qdd_max actually allowed
  double check_dt_s = 0.01;       // samples along a reaching trajectory, s
  double clearance_mm = 20.0;     // extra distance kept from the target sphere
};

enum class Violation { kNone, kPosition, kVelocity, kAcceleration, kCollision, kNotCovered };
const char* to_string(Violation v);

struct LimitCheck {
  Violation violation = Violation::kNone;
  int joint = -1;      // for joint limits
  double t_s = 0.0;    // first sample that breaks it
  double value = 0.0;  // rad, rad/s, rad/s^2, or mm inside the sphere
  bool ok() const { return violation == Violation::kNone; }
};

enum class ReachingStatus { kDirect, kViaIntermediateGoal, kNoFeasibleDuration, kGoalUnreachable };
const char* to_string(ReachingStatus s);

struct ReachingPlan {
  ReachingStatus status = ReachingStatus::kNoFeasibleDuration;
  std::vector<ReachingTrajectory> legs;  // 1 direct, 2 via the intermediate goal
  double t0_s = 0.0;
  double t_land_s = std::numeric_limits<double>::infinity();  // on the final goal trajectory
  int durations_tried = 0;  // reaching trajectories computed (section 9 columns)
  LimitCheck last_refusal;  // why the last refused direct T failed
  std::string reason;       // for logs when not feasible
  bool feasible() const {
    return status == ReachingStatus::kDirect || status == ReachingStatus::kViaIntermediateGoal;
  }
  double duration_s() const { return t_land_s - t0_s; }
  JointSample at(double t_s) const;  // along the legs (first leg's current before t0)
};

class ReachingPlanner {
 public:
  ReachingPlanner(arm::Puma560 arm, ReachingOptions options);

  const ReachingOptions& options() const { return options_; }
  const arm::Puma560& arm() const { return arm_; }

  // Limits (and the sphere, when given) along [t0, t0 + T] of `r`.
  LimitCheck check(const ReachingTrajectory& r, const TargetSphere* target) const;

  // Section 9's scan in joint space: the smallest T whose reaching
  // trajectory from `current` onto `goal` at t0_s breaks no limit.
  // hold_s: the goal trajectory must also cover the hold after landing.
  ReachingPlan shortest(std::shared_ptr<const SampledJointTrajectory> current,
                        std::shared_ptr<const SampledJointTrajectory> goal, double t0_s,
                        const TargetSphere* target, double hold_s = 0.0) const;

  // The whole planner step: the goal pose trajectory (tool pose, base
  // frame, mm) to joint space, the direct scan, and if it fails for a
  // collision or a limit, a safe intermediate goal: a point that moves with
  // the target's centre, outside the sphere, on the tool's side (candidates:
  // the bisector of the directions from the centre to the tool and to the
  // goal, then up, then away from the base axis; at 1.5 and 2.5 times the
  // sphere's radius), with the goal's orientation. The tool reaches it,
  // then the goal from it. The goal is followed in joint space up to
  // horizon_s or until it leaves the arm's reach (a tumbling target turns
  // goals away); landing + hold_s must fall before that.
  ReachingPlan plan(std::shared_ptr<const SampledJointTrajectory> current,
                    const std::function<Eigen::Isometry3d(double)>& goal_pose, double t0_s,
                    double horizon_s, const TargetSphere* target, double hold_s = 0.0) const;

  // The paper's serial-machine heuristic (section 9): the time of a straight
  // line at a safe fraction of the tool's top speed (mm, mm/s).
  static double linear_path_duration(const Eigen::Vector3d& from_mm, const Eigen::Vector3d& to_mm,
                                     double safe_speed_mm_s);

 private:
  arm::Puma560 arm_;
  ReachingOptions options_;
};

}  // namespace ephor::rambo
