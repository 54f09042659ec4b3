#include "procs/shared/arm/command_validator.h"

#include <spdlog/fmt/fmt.h>
#include <cmath>

#include "common/arm/arm_workcell.h"

namespace ephor::arm {

namespace {

Validation reject(std::string reason) {
  Validation v;
  v.reason = std::move(reason);
  return v;
}

}  // namespace

const char* to_string(AckStatus status) {
  switch (status) {
    case AckStatus::kAccepted:
      return "ACCEPTED";
    case AckStatus::kDone:
      return "DONE";
    case AckStatus::kRejected:
      return "REJECTED";
    case AckStatus::kFailed:
      return "FAILED";
  }
  return "UNKNOWN";
}

CommandValidator::CommandValidator(calibration::FieldCalibration calibration,
                                   const geometry::Workcell& cell, ValidatorConfig config)
    : calibration_(std::move(calibration)),
      cell_(cell),
      config_(config),
      arm_(make_puma(cell)),
      collisions_(arm_, cell) {}

Validation CommandValidator::validate(const ArmCommand& cmd, const Joints& current) const {
  switch (cmd.kind) {
    case kKindImage:
      return validate_image(cmd, current);
    case kKindPose:
      return validate_pose(cmd, current);
    case kKindJoints:
      return validate_joints(cmd);
    case kKindTrajectory:
      return validate_trajectory(cmd, current);
    default:
      return reject(fmt::format(
          "unknown goal kind {} (want 0 = image, 1 = pose, 2 = joints, 3 = trajectory)", cmd.kind));
  }
}

std::string CommandValidator::speed_problem(double max_speed_mm_s) const {
  if (!std::isfinite(max_speed_mm_s))
    return fmt::format("speed {} mm/s is not finite", max_speed_mm_s);
  if (max_speed_mm_s < 0.0) return fmt::format("speed {} mm/s is negative", max_speed_mm_s);
  if (max_speed_mm_s > 0.0 && max_speed_mm_s < config_.min_speed_mm_s)
    return fmt::format("speed {} mm/s is below the arm's minimum of {} mm/s (0 asks for the cap)",
                       max_speed_mm_s, config_.min_speed_mm_s);
  if (max_speed_mm_s > config_.max_speed_mm_s)
    return fmt::format("speed {} mm/s is above the arm's cap of {} mm/s", max_speed_mm_s,
                       config_.max_speed_mm_s);
  return {};
}

Validation CommandValidator::validate_image(const ArmCommand& cmd, const Joints& current) const {
  if (!std::isfinite(cmd.u_px) || !std::isfinite(cmd.v_px))
    return reject(fmt::format("target (u, v) = ({}, {}) px is not finite", cmd.u_px, cmd.v_px));
  if (!std::isfinite(cmd.theta_rad))
    return reject(fmt::format("orientation theta {} rad is not finite", cmd.theta_rad));
  if (!std::isfinite(cmd.max_speed_mm_s))
    return reject(fmt::format("speed {} mm/s is not finite", cmd.max_speed_mm_s));
  calibration::Plane plane;
  if (cmd.plane == kPlaneElevation) {
    plane = calibration::Plane::kElevation;
  } else if (cmd.plane == kPlaneObject) {
    plane = calibration::Plane::kObject;
  } else {
    return reject(fmt::format("unknown plane {} (want 0 = elevation or 1 = object)", cmd.plane));
  }
  if (auto why = speed_problem(cmd.max_speed_mm_s); !why.empty()) return reject(why);
  // Pixel centres are at integers; the image spans [-0.5, size - 0.5].
  if (cmd.u_px < -0.5 || cmd.u_px > config_.image_width_px - 0.5 || cmd.v_px < -0.5 ||
      cmd.v_px > config_.image_height_px - 0.5)
    return reject(fmt::format("target (u, v) = ({:.1f}, {:.1f}) px is outside the {} x {} image",
                              cmd.u_px, cmd.v_px, config_.image_width_px, config_.image_height_px));
  if (!current.allFinite()) return reject("the arm's current joints are unknown or not finite");

  const Eigen::Vector2d xy = calibration_.image_to_field(cmd.u_px, cmd.v_px, plane);
  const double z =
      plane == calibration::Plane::kObject ? cell_.object_plane_z_mm : cell_.elevation_plane_z_mm;
  if (!xy.allFinite() || !cell_.inside_field(xy.x(), xy.y()))
    return reject(
        fmt::format("target ({:.1f}, {:.1f}) mm of the field frame is outside the {} x {} mm field",
                    xy.x(), xy.y(), cell_.field_length_mm, cell_.field_width_mm));
  const Eigen::Vector2d dir = calibration_.image_vector_to_field(
      Eigen::Vector2d(std::cos(cmd.theta_rad), std::sin(cmd.theta_rad)), plane);
  Validation v = reach(Eigen::Vector3d(xy.x(), xy.y(), z), std::atan2(dir.y(), dir.x()), current,
                       cmd.max_speed_mm_s);
  v.target.plane = plane;
  return v;
}

Validation CommandValidator::validate_pose(const ArmCommand& cmd, const Joints& current) const {
  const Eigen::Vector3d& p = cmd.position_mm;
  if (!p.allFinite())
    return reject(fmt::format("target ({}, {}, {}) mm is not finite", p.x(), p.y(), p.z()));
  if (!std::isfinite(cmd.theta_rad))
    return reject(fmt::format("orientation theta {} rad is not finite", cmd.theta_rad));
  if (auto why = speed_problem(cmd.max_speed_mm_s); !why.empty()) return reject(why);
  if (!current.allFinite()) return reject("the arm's current joints are unknown or not finite");
  if (!cell_.inside_field(p.x(), p.y()))
    return reject(
        fmt::format("target ({:.1f}, {:.1f}, {:.1f}) mm is outside the work cell's {} x {} mm area",
                    p.x(), p.y(), p.z(), cell_.field_length_mm, cell_.field_width_mm));
  if (p.z() < 0.0 || p.z() > config_.max_tip_height_mm)
    return reject(fmt::format("target height {:.1f} mm is outside [0, {:.0f}] mm above the table",
                              p.z(), config_.max_tip_height_mm));
  return reach(p, cmd.theta_rad, current, cmd.max_speed_mm_s);
}

Validation CommandValidator::validate_joints(const ArmCommand& cmd) const {
  if (!cmd.joints.allFinite()) return reject("joint target is not finite");
  if (auto why = speed_problem(cmd.max_speed_mm_s); !why.empty()) return reject(why);
  const JointLimits& lim = arm_.limits();
  for (int j = 0; j < 6; ++j) {
    if (cmd.joints[j] < lim.q_min[j] || cmd.joints[j] > lim.q_max[j])
      return reject(fmt::format("joint {} target {:.3f} rad is outside [{:.3f}, {:.3f}] rad", j + 1,
                                cmd.joints[j], lim.q_min[j], lim.q_max[j]));
  }
  if (auto hit = collisions_.collision(cmd.joints)) return reject("joint target collides: " + *hit);
  const ToolInField tool = tool_in_field(cell_, cmd.joints);
  Validation v;
  v.target.tip_mm = tool.tip_mm;
  v.target.theta_field_rad = tool.theta_rad;
  v.target.pose_in_base = arm_.forward(cmd.joints);
  v.target.goal_q = cmd.joints;
  v.target.speed_mm_s = cmd.max_speed_mm_s == 0.0 ? config_.max_speed_mm_s : cmd.max_speed_mm_s;
  v.ok = true;
  return v;
}

Validation CommandValidator::validate_trajectory(const ArmCommand& cmd,
                                                 const Joints& current) const {
  const auto& pts = cmd.trajectory.points;
  if (pts.size() < 2)
    return reject(fmt::format("trajectory has {} point(s) (at least 2)", pts.size()));
  if (!current.allFinite()) return reject("the arm's current joints are unknown or not finite");
  const JointLimits& lim = arm_.limits();
  constexpr double kSlack = 1e-6;  // relative, for limits met exactly by the sender
  // relative, for a mean velocity between points (the servo's own slack:
  // float times on the wire round a segment's duration by ~1e-7 s)
  constexpr double kSegmentSlack = 1e-3;
  for (std::size_t k = 0; k < pts.size(); ++k) {
    const TrajectoryPoint& p = pts[k];
    if (!std::isfinite(p.t_s) || !p.q.allFinite() || !p.qd.allFinite())
      return reject(fmt::format("trajectory point {} is not finite", k));
    if (k == 0 && p.t_s != 0.0)
      return reject(fmt::format("trajectory starts at t = {} s (want 0)", p.t_s));
    if (k > 0 && !(p.t_s > pts[k - 1].t_s))
      return reject(
          fmt::format("trajectory time {:.4f} s at point {} does not increase", p.t_s, k));
    for (int j = 0; j < 6; ++j) {
      if (p.q[j] < lim.q_min[j] || p.q[j] > lim.q_max[j])
        return reject(
            fmt::format("trajectory point {} (t {:.3f} s): joint {} at {:.3f} rad is outside "
                        "[{:.3f}, {:.3f}] rad",
                        k, p.t_s, j + 1, p.q[j], lim.q_min[j], lim.q_max[j]));
      if (std::abs(p.qd[j]) > lim.qd_max[j] * (1.0 + kSlack))
        return reject(fmt::format(
            "trajectory point {} (t {:.3f} s): joint {} speed {:.3f} rad/s is above its limit "
            "{:.3f} rad/s",
            k, p.t_s, j + 1, p.qd[j], lim.qd_max[j]));
      if (k > 0) {
        // The servo faults on a segment whose mean velocity is above the
        // limit (common/arm/arm_servo.cc, 0.1 % slack): points at rest 0.3
        // rad apart 0.1 s later pass every point check (fuzz target
        // arm_process).
        const double mean = (p.q[j] - pts[k - 1].q[j]) / (p.t_s - pts[k - 1].t_s);
        if (std::abs(mean) > lim.qd_max[j] * (1.0 + kSegmentSlack))
          return reject(fmt::format(
              "trajectory points {}-{} (t {:.3f}-{:.3f} s): joint {} moves at {:.3f} rad/s on "
              "average, above its limit {:.3f} rad/s",
              k - 1, k, pts[k - 1].t_s, p.t_s, j + 1, mean, lim.qd_max[j]));
        const double qdd = (p.qd[j] - pts[k - 1].qd[j]) / (p.t_s - pts[k - 1].t_s);
        if (std::abs(qdd) > lim.qdd_max[j] * (1.0 + kSlack))
          return reject(fmt::format(
              "trajectory point {} (t {:.3f} s): joint {} acceleration {:.2f} rad/s^2 is above "
              "its limit {:.2f} rad/s^2",
              k, p.t_s, j + 1, qdd, lim.qdd_max[j]));
      }
    }
    if (auto hit = collisions_.collision(p.q))
      return reject(fmt::format("trajectory point {} (t {:.3f} s) collides: ", k, p.t_s) + *hit);
  }
  const double off = (pts.front().q - current).cwiseAbs().maxCoeff();
  if (off > config_.trajectory_start_tolerance_rad)
    return reject(fmt::format(
        "trajectory starts {:.3f} rad from the arm's current joints (at most {:.3f} rad)", off,
        config_.trajectory_start_tolerance_rad));
  const ToolInField tool = tool_in_field(cell_, pts.back().q);
  Validation v;
  v.target.tip_mm = tool.tip_mm;
  v.target.theta_field_rad = tool.theta_rad;
  v.target.pose_in_base = arm_.forward(pts.back().q);
  v.target.goal_q = pts.back().q;
  v.target.speed_mm_s = config_.max_speed_mm_s;
  v.ok = true;
  return v;
}

Validation CommandValidator::reach(const Eigen::Vector3d& tip_mm, double theta_field_rad,
                                   const Joints& current, double max_speed_mm_s) const {
  Validation v;
  v.target.tip_mm = tip_mm;
  v.target.theta_field_rad = theta_field_rad;
  v.target.pose_in_base =
      tool_down_pose(cell_, tip_mm.x(), tip_mm.y(), tip_mm.z(), theta_field_rad);
  const auto q = arm_.nearest_inverse(v.target.pose_in_base, current);
  if (!q) {
    return reject(fmt::format(
        "target ({:.1f}, {:.1f}, {:.1f}) mm of the field frame is out of the PUMA 560's "
        "reach with the tool down ({:.0f} mm from the column)",
        tip_mm.x(), tip_mm.y(), tip_mm.z(),
        distance_from_column_mm(cell_, tip_mm.x(), tip_mm.y())));
  }
  if (auto hit = collisions_.collision(*q)) {
    return reject(fmt::format("target ({:.1f}, {:.1f}, {:.1f}) mm collides: ", tip_mm.x(),
                              tip_mm.y(), tip_mm.z()) +
                  *hit);
  }
  v.target.goal_q = *q;
  v.target.speed_mm_s = max_speed_mm_s == 0.0 ? config_.max_speed_mm_s : max_speed_mm_s;
  v.ok = true;
  return v;
}

}  // namespace ephor::arm
