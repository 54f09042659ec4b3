#include "common/rambo/reaching_planner.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace ephor::rambo {

const char* to_string(Violation v) {
  switch (v) {
    case Violation::kNone:
      return "none";
    case Violation::kPosition:
      return "joint position limit";
    case Violation::kVelocity:
      return "joint velocity limit";
    case Violation::kAcceleration:
      return "joint acceleration limit";
    case Violation::kCollision:
      return "collision with the target";
    case Violation::kNotCovered:
      return "trajectories too short for this duration";
  }
  return "?";
}

const char* to_string(ReachingStatus s) {
  switch (s) {
    case ReachingStatus::kDirect:
      return "direct";
    case ReachingStatus::kViaIntermediateGoal:
      return "via intermediate goal";
    case ReachingStatus::kNoFeasibleDuration:
      return "no feasible duration";
    case ReachingStatus::kGoalUnreachable:
      return "goal unreachable";
  }
  return "?";
}

JointSample ReachingPlan::at(double t_s) const {
  if (legs.empty()) throw std::logic_error("ReachingPlan::at: no legs (plan not feasible)");
  for (const auto& leg : legs) {
    if (t_s <= leg.t_land_s()) return leg.at(t_s);
  }
  return legs.back().at(t_s);
}

ReachingPlanner::ReachingPlanner(arm::Puma560 arm, ReachingOptions options)
    : arm_(std::move(arm)), options_(options) {
  const auto& o = options_;
  if (!(o.duration_min_s > 0.0) || !(o.duration_step_s > 0.0) ||
      !(o.duration_max_s >= o.duration_min_s) || !std::isfinite(o.duration_max_s))
    throw std::invalid_argument("ReachingPlanner: need 0 < duration_min <= duration_max, step > 0");
  if (!(o.limit_fraction > 0.0 && o.limit_fraction <= 1.0))
    throw std::invalid_argument("ReachingPlanner: limit_fraction must be in (0, 1]");
  if (!(o.check_dt_s > 0.0)) throw std::invalid_argument("ReachingPlanner: check_dt_s must be > 0");
  if (!(o.clearance_mm >= 0.0))
    throw std::invalid_argument("ReachingPlanner: clearance must be >= 0 mm");
}

LimitCheck ReachingPlanner::check(const ReachingTrajectory& r, const TargetSphere* target) const {
  const auto& lim = arm_.limits();
  const double f = options_.limit_fraction;
  const int n = static_cast<int>(std::ceil(r.duration_s() / options_.check_dt_s - 1e-9));
  std::vector<JointSample> samples(static_cast<std::size_t>(n + 1));
  std::vector<double> times(samples.size());
  for (int k = 0; k <= n; ++k) {
    times[static_cast<std::size_t>(k)] = std::min(r.t0_s() + k * options_.check_dt_s, r.t_land_s());
    samples[static_cast<std::size_t>(k)] = r.at(times[static_cast<std::size_t>(k)]);
  }
  // Joint limits on every sample first: they are cheap, the sphere needs
  // forward kinematics.
  for (std::size_t k = 0; k < samples.size(); ++k) {
    const JointSample& s = samples[k];
    for (int j = 0; j < 6; ++j) {
      if (s.q[j] < lim.q_min[j] - 1e-9 || s.q[j] > lim.q_max[j] + 1e-9)
        return {Violation::kPosition, j, times[k], s.q[j]};
      if (std::abs(s.qd[j]) > f * lim.qd_max[j] + 1e-9)
        return {Violation::kVelocity, j, times[k], s.qd[j]};
      if (std::abs(s.qdd[j]) > f * lim.qdd_max[j] + 1e-9)
        return {Violation::kAcceleration, j, times[k], s.qdd[j]};
    }
  }
  if (target && target->centre_mm) {
    const double r_min = target->radius_mm + options_.clearance_mm;
    for (std::size_t k = 0; k < samples.size(); ++k) {
      const Eigen::Vector3d c = target->centre_mm(times[k]);
      const Eigen::Isometry3d flange = arm_.flange(samples[k].q);
      const Eigen::Vector3d tip =
          flange.translation() + arm_.tool_length_mm() * flange.linear().col(2);
      const double d = std::min((tip - c).norm(), (flange.translation() - c).norm());
      if (d < r_min) return {Violation::kCollision, -1, times[k], r_min - d};
    }
  }
  return {};
}

ReachingPlan ReachingPlanner::shortest(std::shared_ptr<const SampledJointTrajectory> current,
                                       std::shared_ptr<const SampledJointTrajectory> goal,
                                       double t0_s, const TargetSphere* target,
                                       double hold_s) const {
  ReachingPlan plan;
  plan.t0_s = t0_s;
  if (!current || !goal || !current->covers(t0_s)) {
    plan.reason = "current trajectory does not cover the launch time";
    plan.last_refusal.violation = Violation::kNotCovered;
    return plan;
  }
  const auto& o = options_;
  const int columns = static_cast<int>(std::floor(
                          (o.duration_max_s - o.duration_min_s) / o.duration_step_s + 1e-9)) +
                      1;
  for (int c = 0; c < columns; ++c) {
    const double T = o.duration_min_s + c * o.duration_step_s;
    const double t1 = t0_s + T;
    const bool covered = goal->covers(t1 + hold_s) && (o.method == ReachingMethod::kCubicSpline ||
                                                       (goal->covers(t0_s) && current->covers(t1)));
    if (!covered) {
      // Longer T are not covered either; keep the last limit that refused
      // a covered T (more telling than the end of the prediction).
      if (plan.durations_tried == 0) plan.last_refusal = {Violation::kNotCovered, -1, t1, 0.0};
      break;
    }
    ReachingTrajectory r(o.method, current, goal, t0_s, T);
    ++plan.durations_tried;
    const LimitCheck chk = check(r, target);
    if (chk.ok()) {
      plan.status = ReachingStatus::kDirect;
      plan.t_land_s = r.t_land_s();
      plan.legs.push_back(std::move(r));
      return plan;
    }
    plan.last_refusal = chk;
  }
  std::ostringstream why;
  why << "no duration in [" << o.duration_min_s << ", " << o.duration_max_s
      << "] s is feasible; the last refused broke the " << to_string(plan.last_refusal.violation);
  if (plan.last_refusal.joint >= 0) why << " of joint " << plan.last_refusal.joint + 1;
  plan.reason = why.str();
  return plan;
}

ReachingPlan ReachingPlanner::plan(std::shared_ptr<const SampledJointTrajectory> current,
                                   const std::function<Eigen::Isometry3d(double)>& goal_pose,
                                   double t0_s, double horizon_s, const TargetSphere* target,
                                   double hold_s) const {
  ReachingPlan failed;
  failed.t0_s = t0_s;
  if (!current || !current->covers(t0_s) || !goal_pose || !(horizon_s > 0.0)) {
    failed.status = ReachingStatus::kGoalUnreachable;
    failed.reason = "bad input: current trajectory must cover t0, horizon must be > 0";
    return failed;
  }
  const double dt = current->dt_s();
  const int n = static_cast<int>(std::ceil(horizon_s / dt)) + 1;
  const Joints q_near = current->at(t0_s).q;
  std::string why;
  auto goal_opt =
      joint_trajectory_from_poses(arm_, goal_pose, q_near, t0_s, dt, n, &why, 0.5, true);
  if (!goal_opt) {
    failed.status = ReachingStatus::kGoalUnreachable;
    failed.reason = "goal trajectory: " + why;
    return failed;
  }
  auto goal = std::make_shared<const SampledJointTrajectory>(std::move(*goal_opt));
  ReachingPlan direct = shortest(current, goal, t0_s, target, hold_s);
  if (!direct.feasible() && !why.empty()) direct.reason += " (goal trajectory: " + why + ")";
  if (direct.feasible() || !target || !target->centre_mm) return direct;

  // Safe intermediate goals, fixed relative to the target's centre.
  const Eigen::Vector3d c0 = target->centre_mm(t0_s);
  const Eigen::Isometry3d fl = arm_.flange(q_near);
  const Eigen::Vector3d tool0 = fl.translation() + arm_.tool_length_mm() * fl.linear().col(2);
  const Eigen::Vector3d goal0 = goal_pose(t0_s).translation();
  std::vector<Eigen::Vector3d> dirs;
  const Eigen::Vector3d a = (tool0 - c0).normalized(), b = (goal0 - c0).normalized();
  if ((a + b).norm() > 0.1) dirs.push_back((a + b).normalized());
  dirs.emplace_back(0.0, 0.0, 1.0);
  if (Eigen::Vector2d(c0.x(), c0.y()).norm() > 1.0)
    dirs.push_back(Eigen::Vector3d(c0.x(), c0.y(), 0.0).normalized());
  const double r_safe = target->radius_mm + options_.clearance_mm;
  ReachingPlan best = direct;
  int tried = direct.durations_tried;
  for (const double scale : {1.5, 2.5}) {
    for (const auto& d : dirs) {
      const Eigen::Vector3d offset = scale * r_safe * d;
      auto via_pose = [&](double t) {
        Eigen::Isometry3d p = goal_pose(t);
        p.translation() = target->centre_mm(t) + offset;
        return p;
      };
      auto via_opt =
          joint_trajectory_from_poses(arm_, via_pose, q_near, t0_s, dt, n, nullptr, 0.5, true);
      if (!via_opt) continue;
      auto via = std::make_shared<const SampledJointTrajectory>(std::move(*via_opt));
      ReachingPlan leg1 = shortest(current, via, t0_s, target);
      tried += leg1.durations_tried;
      if (!leg1.feasible()) continue;
      ReachingPlan leg2 = shortest(via, goal, leg1.t_land_s, target, hold_s);
      tried += leg2.durations_tried;
      if (!leg2.feasible()) continue;
      if (best.feasible() && best.t_land_s <= leg2.t_land_s) continue;
      best = ReachingPlan{};
      best.status = ReachingStatus::kViaIntermediateGoal;
      best.t0_s = t0_s;
      best.t_land_s = leg2.t_land_s;
      best.legs = {leg1.legs.front(), leg2.legs.front()};
      best.last_refusal = direct.last_refusal;
    }
  }
  best.durations_tried = tried;
  if (!best.feasible())
    best.reason = "direct: " + direct.reason + "; no safe intermediate goal works either";
  return best;
}

double ReachingPlanner::linear_path_duration(const Eigen::Vector3d& from_mm,
                                             const Eigen::Vector3d& to_mm, double safe_speed_mm_s) {
  if (!(safe_speed_mm_s > 0.0))
    throw std::invalid_argument("linear_path_duration: speed must be > 0");
  return (to_mm - from_mm).norm() / safe_speed_mm_s;
}

}  // namespace ephor::rambo
