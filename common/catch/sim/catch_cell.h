#pragma once
// CatchCell: the PUMA 560 with its cup in the catching work cell, as the
// simulator needs it: the ready pose (cup in the catch plane below the
// board's bottom-edge centre), where the cup is for given joints, the arm as
// capsules for the camera, and the oracle - could an arm at rest at the
// ready pose, told a ball's catch point at release, be there in time?
//
// Frames: W of common/catch/board_model.h, which is F of the work cell
// (common/geometry/workcell.h); mm, rad.

#include <Eigen/Core>

#include "common/arm/puma560.h"
#include "common/catch/sim/board_renderer.h"
#include "common/catch/sim/catch_scenario.h"
#include "common/geometry/workcell.h"
#include "common/motion/motion_planner.h"

namespace ephor::catching {

// ephor-arm's --max-speed-mm-s in deploy/catch.pbtxt: no tool-speed cap in effect.
constexpr double kArmSpeedCapMmS = 10000.0;

class CatchCell {
 public:
  // Throws std::runtime_error when the ready point is out of the arm's reach.
  CatchCell(const CatchScenario& scenario, const geometry::Workcell& cell);

  // The ready point: the catch plane below the bottom edge's centre, W (mm).
  const Eigen::Vector3d& ready_point_w_mm() const { return ready_point_; }
  const arm::Joints& ready_joints() const { return ready_q_; }
  // Where the arm starts: tool down high and back by the column, out of the
  // camera's way while vision finds the board's circles (the cup over the
  // board's foot hid a circle, or was taken for one, on some seeds).
  const arm::Joints& park_joints() const { return park_q_; }
  const arm::Puma560& puma() const { return puma_; }

  // Cup opening centre (the tool tip) for joints q, W (mm).
  Eigen::Vector3d cup_w_mm(const arm::Joints& q) const;
  // Links as capsules and the cup, for BoardRenderer.
  ArmView arm_view(const arm::Joints& q) const;
  // Time the arm needs, from rest at the ready pose, to put the cup at
  // `target_w_mm` (tool down) as ephor-arm would plan it (joint speed and
  // acceleration limits, no tool-speed cap); infinity when unreachable.
  double move_time_from_ready_s(const Eigen::Vector3d& target_w_mm) const;
  // The motion ephor-arm plans for a cup goal (arm_goal_t KIND_POSE, tool
  // down, theta 0) with the arm at joints `from`: the IK solution nearest
  // `from`, the straight line or OMPL, timed at the joint limits (the same
  // MotionPlanner and configuration as the arm server in deploy/catch.pbtxt).
  // Like ephor-arm it plans from rest at `from` whatever the arm's velocity;
  // the servo then catches up (ArmServo). !ok with the reason when refused.
  arm::MotionPlan plan_move(const arm::Joints& from, const Eigen::Vector3d& target_w_mm) const;

 private:
  geometry::Workcell cell_;
  arm::Puma560 puma_;
  arm::MotionPlanner planner_;
  Eigen::Vector3d ready_point_;
  arm::Joints ready_q_;
  arm::Joints park_q_;
};

}  // namespace ephor::catching
