#include "procs/arm/command_validator.h"

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
  if (cmd.max_speed_mm_s < 0.0)
    return reject(fmt::format("speed {} mm/s is negative", cmd.max_speed_mm_s));
  if (cmd.max_speed_mm_s > config_.max_speed_mm_s)
    return reject(fmt::format("speed {} mm/s is above the arm's cap of {} mm/s", cmd.max_speed_mm_s,
                              config_.max_speed_mm_s));
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
  const double theta_f = std::atan2(dir.y(), dir.x());

  Validation v;
  v.target.plane = plane;
  v.target.tip_mm = Eigen::Vector3d(xy.x(), xy.y(), z);
  v.target.theta_field_rad = theta_f;
  v.target.pose_in_base = tool_down_pose(cell_, xy.x(), xy.y(), z, theta_f);
  const auto q = arm_.nearest_inverse(v.target.pose_in_base, current);
  if (!q) {
    return reject(fmt::format(
        "target ({:.1f}, {:.1f}, {:.1f}) mm of the field frame is out of the PUMA 560's "
        "reach with the tool down ({:.0f} mm from the column)",
        xy.x(), xy.y(), z, distance_from_column_mm(cell_, xy.x(), xy.y())));
  }
  if (auto hit = collisions_.collision(*q)) {
    return reject(fmt::format("target ({:.1f}, {:.1f}, {:.1f}) mm collides: ", xy.x(), xy.y(), z) +
                  *hit);
  }
  v.target.goal_q = *q;
  v.target.speed_mm_s = cmd.max_speed_mm_s == 0.0 ? config_.max_speed_mm_s : cmd.max_speed_mm_s;
  v.ok = true;
  return v;
}

}  // namespace ephor::arm
