#include "procs/shepherd/planner/planner_messages.h"

#include <cmath>
#include <cstddef>

#include <Eigen/Core>

#include "common/arm/arm_workcell.h"

namespace ephor::planner {

namespace {

calibration::Plane to_calibration_plane(Plane p) {
  return p == Plane::kObject ? calibration::Plane::kObject : calibration::Plane::kElevation;
}

}  // namespace

std::optional<Plane> arm_plane(const arm_state_t& arm) {
  if (arm.moving) return std::nullopt;
  if (arm.plane == arm_goal_t::PLANE_OBJECT) return Plane::kObject;
  if (arm.plane == arm_goal_t::PLANE_ELEVATION) return Plane::kElevation;
  return std::nullopt;
}

std::optional<ArmModel> arm_model_of(const arm_state_t& arm, const ArmModel& assumed,
                                     const geometry::Workcell& workcell) {
  if (!(std::isfinite(arm.x_mm) && std::isfinite(arm.y_mm) && std::isfinite(arm.z_mm)))
    return std::nullopt;
  ArmModel out = assumed;
  out.x_mm = static_cast<double>(arm.x_mm);
  out.y_mm = static_cast<double>(arm.y_mm);
  out.lowered = static_cast<double>(arm.z_mm) <
                0.5 * (workcell.elevation_plane_z_mm + workcell.object_plane_z_mm);
  // The joints count only when they put the tool where ARM_STATE says it is
  // (a sender without joints leaves them zero).
  out.joints_known = true;
  arm::Joints q;
  for (size_t i = 0; i < 6; ++i) {
    out.joints_rad[i] = arm.q[i];
    q(static_cast<int>(i)) = arm.q[i];
    if (!std::isfinite(arm.q[i])) out.joints_known = false;
  }
  if (out.joints_known) {
    const Eigen::Vector3d tip = arm::tool_in_field(workcell, q).tip_mm;
    if (std::hypot(tip.x() - out.x_mm, tip.y() - out.y_mm) > 20.0) out.joints_known = false;
  }
  return out;
}

std::optional<Sheep> sheep_of(const shepherd_object_t& o) {
  Sheep s;
  s.id = o.id;
  s.x_mm = static_cast<double>(o.x_mm);
  s.y_mm = static_cast<double>(o.y_mm);
  s.vx_mm_s = static_cast<double>(o.vx_mm_s);
  s.vy_mm_s = static_cast<double>(o.vy_mm_s);
  if (o.state == shepherd_object_t::STATE_VISIBLE) {
    s.state = SheepState::kVisible;
  } else if (o.state == shepherd_object_t::STATE_OBSCURED) {
    s.state = SheepState::kObscured;
  } else if (o.state == shepherd_object_t::STATE_DEAD) {
    s.state = SheepState::kDead;
  } else {
    return std::nullopt;
  }
  return s;
}

arm_goal_t goal_message_of(const Goal& goal, const calibration::FieldCalibration& calibration,
                           int64_t goal_id_offset, int64_t source_utime) {
  const auto plane = to_calibration_plane(goal.plane);
  const Eigen::Vector2d p = calibration.field_to_image(goal.x_mm, goal.y_mm, plane);
  // Orientation: the image direction of a short step along theta in F.
  const Eigen::Vector2d q =
      calibration.field_to_image(goal.x_mm + 10.0 * std::cos(goal.theta_rad),
                                 goal.y_mm + 10.0 * std::sin(goal.theta_rad), plane);
  arm_goal_t msg{};
  msg.kind = arm_goal_t::KIND_IMAGE;
  msg.goal_id = goal.goal_id + goal_id_offset;
  msg.plane = goal.plane == Plane::kObject ? arm_goal_t::PLANE_OBJECT : arm_goal_t::PLANE_ELEVATION;
  msg.u = static_cast<float>(p.x());
  msg.v = static_cast<float>(p.y());
  msg.theta_rad = static_cast<float>(std::atan2(q.y() - p.y(), q.x() - p.x()));
  // The arm's own cap: --arm-speed-mm-s is what the planner assumes (set it
  // lower than the cap to plan conservatively), not a request to slow down.
  msg.max_speed_mm_s = 0.0f;
  msg.source_frame_utime = source_utime;
  msg.target_object = goal.target;
  return msg;
}

int64_t planner_goal_id(int64_t arm_goal_id, int64_t goal_id_offset) {
  // A goal id far below the offset (a sender's garbage, e.g. INT64_MIN)
  // overflowed the subtraction (fuzz target shepherd_planner): no goal of
  // this planner has it.
  int64_t id = 0;
  if (__builtin_sub_overflow(arm_goal_id, goal_id_offset, &id)) return -1;
  return id;
}

shepherd_planner_status_t status_message_of(const PlannerStatus& st, const std::string& kind,
                                            const calibration::FieldCalibration& calibration,
                                            int64_t goal_id_offset, int64_t source_utime,
                                            float planning_us) {
  shepherd_planner_status_t msg{};
  msg.utime = source_utime;
  msg.planner = kind;
  msg.phase = st.phase;
  msg.target_object = st.target;
  const Eigen::Vector2d ic =
      calibration.field_to_image(st.intercept_x_mm, st.intercept_y_mm, calibration::Plane::kObject);
  msg.intercept_u = static_cast<float>(ic.x());
  msg.intercept_v = static_cast<float>(ic.y());
  msg.intercept_time_s = static_cast<float>(st.intercept_time_s);
  msg.num_candidates = st.num_candidates;
  msg.planning_us = planning_us;
  msg.goal_id = st.goal_id + goal_id_offset;
  return msg;
}

}  // namespace ephor::planner
