#include "common/rambo/tagging_planner.h"

#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include "common/rambo/reaching_planner.h"
#include "common/rambo/rigid_body_pose_predictor.h"
#include "common/rambo/task_orderer.h"

namespace ephor::rambo {

Eigen::Isometry3d FittedMotion::pose(double t_s) const {
  if (polynomial) return polynomial->pose(t_s);
  Eigen::Quaterniond q = orientation;
  Eigen::Vector3d w = body_rates_rad_s;
  RigidBodyPosePredictor::propagate(principal_moments, 0.005, t_s - t_ref_s, &q, &w);
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.linear() = q.normalized().toRotationMatrix();
  p.translation() = position_mm + velocity_mm_s * (t_s - t_ref_s);
  return p;
}

JointSample TaggingTrajectory::at(double t_s) const {
  if (samples.empty()) return {};
  const double u = (t_s - t0_s) / dt_s;
  if (!(u > 0.0)) return samples.front();
  const auto k = static_cast<std::size_t>(u);
  if (k + 1 >= samples.size()) {
    JointSample rest;
    rest.q = samples.back().q;
    return rest;
  }
  const double a = u - static_cast<double>(k);
  const JointSample& s0 = samples[k];
  const JointSample& s1 = samples[k + 1];
  JointSample js;
  js.q = (1.0 - a) * s0.q + a * s1.q;
  js.qd = (1.0 - a) * s0.qd + a * s1.qd;
  js.qdd = (1.0 - a) * s0.qdd + a * s1.qdd;
  return js;
}

bool FittedMotion::finite() const {
  return std::isfinite(t_ref_s) && position_mm.allFinite() && velocity_mm_s.allFinite() &&
         orientation.coeffs().allFinite() && orientation.norm() > 0.5 &&
         body_rates_rad_s.allFinite() && principal_moments.allFinite() &&
         principal_moments.minCoeff() > 0.0 && (!polynomial || polynomial->valid());
}

namespace {

// The fitted motion sampled every kStepS from t0_s (RK4 once along the way),
// so that ordering, which asks for the target's pose at many launch and
// arrival times (109 600 reaching trajectories for 8 diodes, exhaustive),
// does not integrate Euler's equations from t_ref each time. Between samples:
// the position exactly (constant velocity), the orientation by slerp (at the
// slow tumbles here, well under 0.001 deg from the integrated one). Beyond
// the table: the motion itself.
class SampledMotion {
 public:
  static constexpr double kStepS = 0.01;
  SampledMotion(const FittedMotion& m, double t0_s, double span_s) : m_(m), t0_s_(t0_s) {
    if (m.polynomial) return;  // cheap to evaluate: no table
    Eigen::Quaterniond q = m.orientation;
    Eigen::Vector3d w = m.body_rates_rad_s;
    RigidBodyPosePredictor::propagate(m.principal_moments, 0.005, t0_s - m.t_ref_s, &q, &w);
    const auto n = static_cast<std::size_t>(std::ceil(span_s / kStepS)) + 1;
    q_.reserve(n);
    q_.push_back(q.normalized());
    for (std::size_t k = 1; k < n; ++k) {
      RigidBodyPosePredictor::propagate(m.principal_moments, 0.005, kStepS, &q, &w);
      q_.push_back(q.normalized());
    }
  }
  Eigen::Isometry3d pose(double t_s) const {
    const double u = (t_s - t0_s_) / kStepS;
    if (q_.empty() || !(u >= 0.0) || u >= static_cast<double>(q_.size() - 1)) return m_.pose(t_s);
    const auto k = static_cast<std::size_t>(u);
    Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
    p.linear() = q_[k].slerp(u - static_cast<double>(k), q_[k + 1]).toRotationMatrix();
    p.translation() = m_.position_mm + m_.velocity_mm_s * (t_s - m_.t_ref_s);
    return p;
  }

 private:
  FittedMotion m_;
  double t0_s_;
  std::vector<Eigen::Quaterniond> q_;
};

}  // namespace

TaggingPlanner::TaggingPlanner(const RamboCell& cell, TaggingOptions options)
    : cell_(cell), options_(options), arm_(cell.tool_length_mm) {}

std::optional<arm::Joints> TaggingPlanner::goal_joints(int diode, const FittedMotion& m, double t_s,
                                                       const arm::Joints& near) const {
  return arm_.nearest_inverse(m.pose(t_s) * cell_.goal_in_target(diode), near);
}

std::optional<arm::Joints> TaggingPlanner::goal_joints_at(int diode,
                                                          const Eigen::Isometry3d& target_in_base,
                                                          const arm::Joints& near) const {
  return arm_.nearest_inverse(target_in_base * cell_.goal_in_target(diode), near);
}

TaggingStep TaggingPlanner::step(double now_s, const FittedMotion& motion,
                                 const std::vector<bool>& tagged, const arm::Joints& current_q) {
  TaggingStep s;
  if (!motion.finite() || !current_q.allFinite()) {
    s.status = "no usable prediction or arm state";
    return s;
  }
  const int n = static_cast<int>(cell_.diodes.size());
  std::vector<int> open;
  for (int i = 0; i < n; ++i)
    if (i >= static_cast<int>(tagged.size()) || !tagged[static_cast<std::size_t>(i)])
      open.push_back(i);
  if (open.empty()) {
    task_ = -1;
    s.status = "all diodes tagged";
    return s;
  }
  const double hold_s = options_.required_s + options_.hold_margin_s;
  const bool keep = task_ >= 0 && std::find(open.begin(), open.end(), task_) != open.end() &&
                    goal_joints(task_, motion, now_s + options_.lead_s, current_q).has_value();
  if (!keep) {
    // Every task's reach and hold, one after the other, within this span.
    const double span_s =
        static_cast<double>(open.size()) * (hold_s + 5.0 + options_.settle_s) + 2.0;
    const SampledMotion sampled(motion, now_s, span_s);
    // Only diodes whose goal the arm can hold now are ordered; the others
    // come back when the tumble turns them towards the arm.
    std::vector<int> reachable;
    for (int i : open)
      if (goal_joints_at(i, sampled.pose(now_s + 1.0), current_q) &&
          goal_joints_at(i, sampled.pose(now_s + 1.0 + hold_s), current_q))
        reachable.push_back(i);
    open = reachable;
    // Section 10 over the open diodes; cost: the straight-line heuristic.
    const Eigen::Vector3d tool_now = arm_.forward(current_q).translation();
    // Returns a Vector3d, not Eigen's translation() block: that would point
    // into the pose product, a temporary gone when the lambda returns
    // (AddressSanitizer: stack-use-after-scope).
    auto goal_pos = [&](int k, double t) -> Eigen::Vector3d {
      return (sampled.pose(t) * cell_.goal_in_target(open[static_cast<std::size_t>(k)]))
          .translation();
    };
    ReachingDurationFn cost = [&](int from, int to, double launch_s) {
      const Eigen::Vector3d a =
          from == TaskOrderer::kInitialTrajectory ? tool_now : goal_pos(from, launch_s);
      const double t = ReachingPlanner::linear_path_duration(a, goal_pos(to, launch_s),
                                                             options_.safe_speed_mm_s) +
                       options_.settle_s;
      const int d = open[static_cast<std::size_t>(to)];
      if (!goal_joints_at(d, sampled.pose(launch_s + t), current_q) ||
          !goal_joints_at(d, sampled.pose(launch_s + t + hold_s), current_q))
        return std::numeric_limits<double>::infinity();
      return t;
    };
    const TaskOrderer orderer(std::vector<double>(open.size(), hold_s), cost);
    const TaskOrder g = orderer.greedy(now_s);
    const TaskOrder e = orderer.exhaustive(now_s);
    const TaskOrder d = orderer.dynamic_programming(now_s);
    s.reordered = true;
    s.greedy_trajectories = g.reaching_trajectories;
    s.exhaustive_trajectories = e.reaching_trajectories;
    s.dp_trajectories = d.reaching_trajectories;
    s.order_total_s = d.total_time_s;
    // DP orders all tasks or none; when no order reaches them all, greedy's
    // (as far as it gets) is followed.
    const std::vector<int>& first = d.feasible && !d.order.empty() ? d.order : g.order;
    for (int k : first) s.order.push_back(open[static_cast<std::size_t>(k)]);
    task_ = first.empty() ? -1 : open[static_cast<std::size_t>(first.front())];
    last_order_ = s;
  } else {
    s.order = last_order_.order;
    s.greedy_trajectories = last_order_.greedy_trajectories;
    s.exhaustive_trajectories = last_order_.exhaustive_trajectories;
    s.dp_trajectories = last_order_.dp_trajectories;
    s.order_total_s = last_order_.order_total_s;
  }
  s.task = task_;
  if (task_ < 0) {
    s.status = "no diode within reach of the predicted motion";
    return s;
  }
  s.goal_q = goal_joints(task_, motion, now_s + options_.lead_s, current_q);
  s.status = s.goal_q ? "following diode " + cell_.diodes[static_cast<std::size_t>(task_)].name
                      : "goal out of reach";
  return s;
}

std::optional<TaggingTrajectory> TaggingPlanner::reaching_trajectory(
    int diode, double now_s, const FittedMotion& motion, const arm::Joints& q,
    const arm::Joints& qd, std::string* why, double limit_fraction,
    const TaggingTrajectory* from) const {
  if (diode < 0 || diode >= static_cast<int>(cell_.diodes.size()) || !motion.finite() ||
      !q.allFinite() || !qd.allFinite() || (from && from->samples.empty())) {
    if (why) *why = "no such diode, or a non-finite motion or arm state";
    return std::nullopt;
  }
  ReachingOptions ro;
  ro.limit_fraction = limit_fraction;
  const ReachingPlanner reacher(arm_, ro);
  const double hold_s = options_.required_s + options_.hold_margin_s;
  const double horizon_s = ro.duration_max_s + hold_s + 1.0;
  const SampledMotion sampled(motion, now_s, horizon_s + 1.0);
  const double dt = 0.01;
  const int n = static_cast<int>(std::ceil(horizon_s / dt)) + 1;
  auto current = std::make_shared<const SampledJointTrajectory>(
      SampledJointTrajectory::from_function(now_s, dt, n, [&](double t) {
        if (from) return from->at(t);
        JointSample js;
        js.q = q + qd * (t - now_s);
        js.qd = qd;
        return js;
      }));
  const Eigen::Isometry3d goal_in_target = cell_.goal_in_target(diode);
  const Eigen::Vector3d centre = cell_.model.centre();
  TargetSphere sphere;
  sphere.centre_mm = [&](double t) { return sampled.pose(t) * centre; };
  sphere.radius_mm = cell_.model.bounding_radius_mm();
  const ReachingPlan plan = reacher.plan(
      current, [&](double t) { return sampled.pose(t) * goal_in_target; }, now_s, horizon_s,
      &sphere, hold_s);
  if (!plan.feasible()) {
    if (why) *why = plan.reason.empty() ? to_string(plan.status) : plan.reason;
    return std::nullopt;
  }
  TaggingTrajectory out;
  out.diode = diode;
  out.t0_s = now_s;
  out.t_land_s = plan.t_land_s;
  out.durations_tried = plan.durations_tried;
  out.via_intermediate_goal = plan.status == ReachingStatus::kViaIntermediateGoal;
  out.hold_end_s = plan.t_land_s + hold_s;
  const int samples = static_cast<int>(std::ceil((out.hold_end_s - now_s) / out.dt_s)) + 1;
  for (int k = 0; k < samples; ++k)
    out.samples.push_back(plan.at(now_s + out.dt_s * static_cast<double>(k)));
  out.hold_end_s = out.end_s();
  // The stop: every joint at constant deceleration, all at rest together.
  const JointSample last = plan.at(out.hold_end_s);  // = the last sample
  const arm::JointLimits& lim = arm_.limits();
  double stop_s = 0.0;
  for (int j = 0; j < 6; ++j)
    stop_s = std::max(stop_s, std::abs(last.qd[j]) / (0.5 * lim.qdd_max[j]));
  const int stop_samples = static_cast<int>(std::ceil(stop_s / out.dt_s));
  if (stop_samples > 0) {
    const double stop_total_s = out.dt_s * static_cast<double>(stop_samples);
    const arm::Joints decel = last.qd / stop_total_s;
    for (int k = 1; k <= stop_samples; ++k) {
      const double t = out.dt_s * static_cast<double>(k);
      JointSample js;
      js.q = last.q + last.qd * t - 0.5 * decel * t * t;
      js.qd = last.qd - decel * t;
      js.qdd = -decel;
      out.samples.push_back(js);
    }
  }
  // Every sample within the joint position limits: the stop after a hold
  // that ends moving towards a limit can pass it (fuzz target
  // rambo_planner: joint 5 at -1.7464 rad, its limit -1.7453), and the arm
  // refuses such a trajectory whole. The planner sends a joint goal instead.
  for (std::size_t k = 0; k < out.samples.size(); ++k) {
    if (!lim.within(out.samples[k].q)) {
      if (why)
        *why = "the reaching trajectory leaves the joint limits at sample " + std::to_string(k) +
               " of " + std::to_string(out.samples.size());
      return std::nullopt;
    }
  }
  return out;
}

}  // namespace ephor::rambo
