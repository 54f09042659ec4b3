#include "common/motion/motion_planner.h"

#include <spdlog/fmt/fmt.h>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "common/arm/tool_line.h"
#include "common/motion/joint_path_timing.h"
#include "common/motion/trapezoid_profile.h"

namespace ephor::arm {

const char* to_string(MotionKind kind) {
  switch (kind) {
    case MotionKind::kStay:
      return "stay";
    case MotionKind::kCartesian:
      return "cartesian";
    case MotionKind::kJointSpace:
      return "joint-space";
  }
  return "unknown";
}

MotionPlanner::MotionPlanner(const geometry::Workcell& cell, MotionPlannerConfig config)
    : cell_(cell),
      config_(config),
      arm_(cell.tool_length_mm),
      collisions_(arm_, cell, config.collision),
      joint_planner_(arm_.limits(), config.joint_planner) {
  if (!(config_.max_speed_mm_s > 0.0) || !std::isfinite(config_.max_speed_mm_s))
    throw std::invalid_argument("MotionPlanner: max speed must be > 0 mm/s");
}

std::optional<std::string> MotionPlanner::check_cartesian(const Joints& start,
                                                          const Eigen::Isometry3d& goal_in_base,
                                                          const Joints& goal_q,
                                                          double min_tip_z_mm) const {
  const ToolLine line(arm_.forward(start), goal_in_base);
  const int n =
      std::max(1, static_cast<int>(std::ceil(std::max(line.length_mm() / config_.check_step_mm,
                                                      line.angle_rad() / config_.check_step_rad))));
  std::string hit;
  Joints end = start;
  const auto stop = line.follow(
      arm_, start, n, config_.max_joint_step_rad,
      [&](const Joints& q) {
        if (auto h = collisions_.collision(q, min_tip_z_mm)) hit = *h;
        return hit.empty();
      },
      &end);
  if (stop) {
    switch (stop->kind) {
      case LineBreak::Kind::kUnreachable:
        return fmt::format("the straight line leaves the reachable workspace {:.0f} % of the way",
                           100 * stop->u);
      case LineBreak::Kind::kJump:
        return fmt::format(
            "the straight line changes IK branch or passes a singularity {:.0f} % of the way "
            "(joint jump {:.2f} rad)",
            100 * stop->u, stop->jump_rad);
      case LineBreak::Kind::kRejected:
        return fmt::format("the straight line collides {:.0f} % of the way: ", 100 * stop->u) + hit;
    }
  }
  if ((end - goal_q).cwiseAbs().maxCoeff() > 1e-6)
    return std::string(
        "the straight line ends in another IK branch than the one nearest the start");
  return std::nullopt;
}

MotionPlan MotionPlanner::plan(const Joints& start, const Eigen::Isometry3d& goal_in_base,
                               double speed_mm_s) const {
  MotionPlan out;
  if (!start.allFinite()) {
    out.reason = "current joints are not finite";
    return out;
  }
  if (!goal_in_base.matrix().allFinite()) {
    out.reason = "goal pose is not finite";
    return out;
  }
  if (!(speed_mm_s >= 0.0) || !std::isfinite(speed_mm_s)) {
    out.reason = "requested speed must be finite and >= 0 mm/s";
    return out;
  }
  const double speed =
      speed_mm_s == 0.0 ? config_.max_speed_mm_s : std::min(speed_mm_s, config_.max_speed_mm_s);
  out.requested_speed_mm_s = speed;
  const auto goal_q = arm_.nearest_inverse(goal_in_base, start);
  if (!goal_q) {
    out.reason = "goal pose is out of reach of the PUMA 560 within its joint limits";
    return out;
  }
  out.goal_q = *goal_q;
  const double base_z = cell_.base_z_mm;
  const double min_tip_z =
      std::min(arm_.forward(start).translation().z(), goal_in_base.translation().z()) + base_z -
      config_.tip_height_margin_mm;
  if (auto hit = collisions_.collision(*goal_q, min_tip_z)) {
    out.reason = "goal pose collides: " + *hit;
    return out;
  }
  auto why_not_line = check_cartesian(start, goal_in_base, *goal_q, min_tip_z);
  if (!why_not_line) {
    MotionPlan p = plan_cartesian(start, goal_in_base, *goal_q, speed);
    if (p.ok) return p;
    why_not_line = p.reason;
  }
  MotionPlan p = plan_joint_space(start, *goal_q, speed, min_tip_z);
  p.cartesian_rejected = *why_not_line;
  if (!p.ok) p.reason = "straight line not possible (" + *why_not_line + "); " + p.reason;
  return p;
}

MotionPlan MotionPlanner::plan_cartesian(const Joints& start, const Eigen::Isometry3d& goal_in_base,
                                         const Joints& goal_q, double speed_mm_s) const {
  MotionPlan out;
  out.goal_q = goal_q;
  out.requested_speed_mm_s = speed_mm_s;
  const ToolLine line(arm_.forward(start), goal_in_base);
  const double length =
      std::max(line.length_mm(), config_.turn_equivalent_mm_per_rad * line.angle_rad());
  if (length < 1e-6 && (goal_q - start).cwiseAbs().maxCoeff() < 1e-9) {
    out.ok = true;
    out.kind = MotionKind::kStay;
    out.trajectory.points.push_back({0.0, goal_q, Joints::Zero()});
    return out;
  }
  const TrapezoidProfile profile(length, speed_mm_s, config_.cartesian_accel_mm_s2);
  const Puma560& arm = arm_;
  const TimedPath path = [&](double t, const Joints& previous,
                             std::string* why) -> std::optional<Joints> {
    const double u = length > 0.0 ? profile.position(t) / length : 1.0;
    if (u >= 1.0 - 1e-12) return goal_q;
    auto q = arm.nearest_inverse(line.at(u), previous);
    if (!q && why) *why = "inverse kinematics failed along the line";
    return q;
  };
  ScalingConfig scaling = config_.scaling;
  scaling.max_tool_speed_mm_s = speed_mm_s * 1.001;  // finite differences of an exact line
  const ScaledTrajectory scaled =
      SpeedScaler(arm_, scaling).scale(path, profile.duration_s(), start);
  if (!scaled.ok) {
    out.reason = scaled.reason;
    return out;
  }
  out.ok = true;
  out.kind = MotionKind::kCartesian;
  out.trajectory = scaled.trajectory;
  out.speed_scale = 1.0 / scaled.stretch;
  out.peak_tool_speed_mm_s = scaled.peak_tool_speed_mm_s;
  out.velocity_ratio = scaled.velocity_ratio;
  out.acceleration_ratio = scaled.acceleration_ratio;
  return out;
}

MotionPlan MotionPlanner::plan_joint_space(const Joints& start, const Joints& goal_q,
                                           double speed_mm_s, double min_tip_z_mm) const {
  MotionPlan out;
  out.goal_q = goal_q;
  out.requested_speed_mm_s = speed_mm_s;
  out.kind = MotionKind::kJointSpace;
  out.joint_path = joint_planner_.plan(start, goal_q, [this, min_tip_z_mm](const Joints& q) {
    return collisions_.clear(q, min_tip_z_mm);
  });
  if (out.joint_path.status != JointPathStatus::kFound) {
    out.reason = std::string("joint-space path ") + to_string(out.joint_path.status) + ": " +
                 out.joint_path.reason;
    return out;
  }
  // Straight joint segments from rest to rest, timed along a velocity-limit
  // curve (JointPathTiming); the scaler then verifies (and if need be slows).
  const JointPathTiming timing(arm_, out.joint_path.waypoints, speed_mm_s,
                               config_.scaling.limit_fraction);
  const TimedPath path = [&](double t, const Joints&, std::string*) -> std::optional<Joints> {
    return timing.at(t);
  };
  const double total = timing.duration_s();
  ScalingConfig scaling = config_.scaling;
  scaling.max_tool_speed_mm_s = speed_mm_s * 1.001;
  const ScaledTrajectory scaled = SpeedScaler(arm_, scaling).scale(path, total, start);
  if (!scaled.ok) {
    out.reason = scaled.reason;
    return out;
  }
  out.ok = true;
  out.trajectory = scaled.trajectory;
  out.speed_scale = 1.0 / scaled.stretch;
  out.peak_tool_speed_mm_s = scaled.peak_tool_speed_mm_s;
  out.velocity_ratio = scaled.velocity_ratio;
  out.acceleration_ratio = scaled.acceleration_ratio;
  return out;
}

}  // namespace ephor::arm
