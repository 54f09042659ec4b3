#include "common/catch/sim/catch_cell.h"

#include <limits>
#include <stdexcept>

#include "common/arm/arm_workcell.h"

namespace ephor::catching {

namespace {

// As ephor-arm plans in the catching manifest: no tool-speed cap (the joint
// limits bound the motion) and the work cell's tool acceleration.
arm::MotionPlannerConfig as_the_arm_plans(const geometry::Workcell& cell) {
  arm::MotionPlannerConfig c;
  c.max_speed_mm_s = kArmSpeedCapMmS;
  c.cartesian_accel_mm_s2 = cell.tool_accel_mm_s2;
  return c;
}

}  // namespace

CatchCell::CatchCell(const CatchScenario& scenario, const geometry::Workcell& cell)
    : cell_(cell), puma_(arm::make_puma(cell)), planner_(cell, as_the_arm_plans(cell)) {
  ready_point_ = catching::ready_point_w_mm(scenario.board, scenario.placement);
  const auto q = puma_.nearest_inverse(
      arm::tool_down_pose(cell_, ready_point_.x(), ready_point_.y(), ready_point_.z(), 0.0),
      arm::reference_joints());
  if (!q)
    throw std::runtime_error(
        "the catch ready point is out of the PUMA 560's reach: check the work cell");
  ready_q_ = *q;
  // 300 mm out from the column, 600 mm up: clear of every seed's view of the
  // circles in the seeds tried (1-20).
  const Eigen::Vector3d park(cell.base_x_mm + 300.0, cell.base_y_mm, 600.0);
  const auto p = puma_.nearest_inverse(
      arm::tool_down_pose(cell_, park.x(), park.y(), park.z(), 0.0), ready_q_);
  if (!p)
    throw std::runtime_error(
        "the catch park point is out of the PUMA 560's reach: check the work cell");
  park_q_ = *p;
}

Eigen::Vector3d CatchCell::cup_w_mm(const arm::Joints& q) const {
  return arm::tool_in_field(cell_, q).tip_mm;
}

ArmView CatchCell::arm_view(const arm::Joints& q) const {
  ArmView view;
  const auto frames = puma_.link_frames(q);
  Eigen::Vector3d previous = arm::base_point_to_field(cell_, Eigen::Vector3d::Zero());
  // The column from the table to the shoulder.
  view.links_w.push_back({Eigen::Vector3d(previous.x(), previous.y(), 0.0), previous, 70.0});
  const double radii[6] = {60.0, 55.0, 45.0, 40.0, 35.0, 30.0};
  for (int i = 1; i <= 6; ++i) {
    const Eigen::Vector3d p = arm::base_point_to_field(cell_, frames[i].translation());
    if ((p - previous).norm() > 1.0) view.links_w.push_back({previous, p, radii[i - 1]});
    previous = p;
  }
  const Eigen::Vector3d tip = cup_w_mm(q);
  view.links_w.push_back({previous, tip, 20.0});  // the cup's stem
  view.cup_opening_w_mm = tip;
  return view;
}

double CatchCell::move_time_from_ready_s(const Eigen::Vector3d& target_w_mm) const {
  const auto plan = plan_move(ready_q_, target_w_mm);
  if (!plan.ok) return std::numeric_limits<double>::infinity();
  return plan.trajectory.duration_s();
}

arm::MotionPlan CatchCell::plan_move(const arm::Joints& from,
                                     const Eigen::Vector3d& target_w_mm) const {
  if (!from.allFinite() || !target_w_mm.allFinite()) {
    arm::MotionPlan refused;
    refused.reason = "the arm's joints or the cup goal are not finite";
    return refused;
  }
  return planner_.plan(
      from, arm::tool_down_pose(cell_, target_w_mm.x(), target_w_mm.y(), target_w_mm.z(), 0.0),
      kArmSpeedCapMmS);
}

}  // namespace ephor::catching
