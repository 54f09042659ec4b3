#include "procs/shepherd/planner/puma_arm_motion.h"

#include <algorithm>

#include "common/arm/arm_workcell.h"

namespace ephor::planner {

namespace {

arm::MotionPlannerConfig with_tool_cap(double speed_mm_s) {
  arm::MotionPlannerConfig c;
  c.max_speed_mm_s = speed_mm_s;  // as ephor-arm --max-speed-mm-s
  return c;
}

}  // namespace

PumaArmMotion::PumaArmMotion(const geometry::Workcell& cell, double speed_mm_s)
    : cell_(cell),
      speed_mm_s_(speed_mm_s),
      planner_(cell, with_tool_cap(speed_mm_s)),
      q_(arm::park_joints(cell)) {}

bool PumaArmMotion::start(double x_mm, double y_mm, double z_mm, double theta_rad) {
  const arm::MotionPlan plan =
      planner_.plan(q_, arm::tool_down_pose(cell_, x_mm, y_mm, z_mm, theta_rad), speed_mm_s_);
  if (!plan.ok || plan.trajectory.empty()) return false;
  trajectory_ = plan.trajectory;
  t_s_ = 0.0;
  ++moves_;
  move_time_s_ += trajectory_.duration_s();
  if (plan.kind == arm::MotionKind::kJointSpace) {
    ++joint_space_moves_;
    joint_space_time_s_ += trajectory_.duration_s();
  }
  return true;
}

bool PumaArmMotion::step(double dt_s) {
  if (trajectory_.empty()) return true;
  t_s_ += dt_s;
  const auto& pts = trajectory_.points;
  if (t_s_ >= trajectory_.duration_s()) {
    q_ = pts.back().q;
    trajectory_.points.clear();
    return true;
  }
  // Linear between the trajectory's samples (the servo period).
  const auto it =
      std::upper_bound(pts.begin(), pts.end(), t_s_,
                       [](double t, const arm::TrajectoryPoint& p) { return t < p.t_s; });
  const auto& b = *it;
  const auto& a = *(it - 1);
  const double u = b.t_s > a.t_s ? (t_s_ - a.t_s) / (b.t_s - a.t_s) : 1.0;
  q_ = a.q + u * (b.q - a.q);
  return false;
}

std::array<double, 3> PumaArmMotion::tool_mm() const {
  const Eigen::Vector3d p = arm::tool_in_field(cell_, q_).tip_mm;
  return {p.x(), p.y(), p.z()};
}

JointAngles PumaArmMotion::joints() const {
  JointAngles out{};
  for (int i = 0; i < 6; ++i) out[static_cast<size_t>(i)] = q_(i);
  return out;
}

}  // namespace ephor::planner
