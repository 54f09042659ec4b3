#include "procs/shepherd/planner/arm_configuration.h"

#include <algorithm>
#include <cmath>

#include "common/arm/tool_line.h"

namespace ephor::planner {

ArmConfiguration::ArmConfiguration(const geometry::Workcell& cell)
    : cell_(cell), puma_(arm::make_puma(cell)) {}

int ArmConfiguration::of(const JointAngles& q) const {
  arm::Joints j;
  for (int i = 0; i < 6; ++i) j(i) = q[static_cast<size_t>(i)];
  return of(j);
}

int ArmConfiguration::of(const arm::Joints& q) const {
  // Frames of the standard DH model: [1] shoulder (joint 2's axis is its z),
  // [2] elbow, [4] wrist centre.
  const auto frames = puma_.link_frames(q);
  const Eigen::Vector3d shoulder = frames[1].translation();
  const Eigen::Vector3d elbow = frames[2].translation();
  const Eigen::Vector3d wrist = frames[4].translation();
  // Reach direction: frame 1's x axis (horizontal, turned by joint 1).
  const Eigen::Vector3d reach = frames[1].linear().col(0);
  const Eigen::Vector3d axis2 = frames[1].linear().col(2);
  const bool over = (wrist - shoulder).dot(reach) < 0.0;
  const bool elbow_down = (elbow - shoulder).cross(wrist - shoulder).dot(axis2) < 0.0;
  return (over ? 1 : 0) | (elbow_down ? 2 : 0);
}

bool ArmConfiguration::needs_switch(const JointAngles& q, double x_mm, double y_mm, double z_mm,
                                    double theta_rad) const {
  const auto solutions = puma_.inverse(arm::tool_down_pose(cell_, x_mm, y_mm, z_mm, theta_rad));
  if (solutions.empty()) return false;
  const int current = of(q);
  for (const arm::Joints& s : solutions) {
    if (of(s) == current) return false;
  }
  return true;
}

bool ArmConfiguration::line_needs_detour(const JointAngles& q, double x_mm, double y_mm,
                                         double z_mm, double theta_rad, double step_mm) const {
  // A jump of more than this between samples (rad) is a branch change or a
  // limit: 40 mm steps at >= 345 mm from the column turn joint 1 by < 0.12
  // rad, and the jumps seen on the full system were 2.8-6.3 rad.
  constexpr double kJumpRad = 1.0;
  arm::Joints current;
  for (int i = 0; i < 6; ++i) current(i) = q[static_cast<size_t>(i)];
  const arm::ToolLine line(puma_.forward(current),
                           arm::tool_down_pose(cell_, x_mm, y_mm, z_mm, theta_rad));
  const int n = static_cast<int>(std::ceil(line.length_mm() / step_mm));
  return line.follow(puma_, current, n, kJumpRad).has_value();
}

std::optional<double> ArmConfiguration::joint1_turn_rad(const JointAngles& q, double x_mm,
                                                        double y_mm, double z_mm,
                                                        double theta_rad) const {
  arm::Joints current;
  for (int i = 0; i < 6; ++i) current(i) = q[static_cast<size_t>(i)];
  const int configuration = of(current);
  std::optional<double> turn;
  for (const arm::Joints& s :
       puma_.inverse(arm::tool_down_pose(cell_, x_mm, y_mm, z_mm, theta_rad))) {
    if (of(s) != configuration) continue;
    const double t = s(0) - current(0);
    if (!turn || std::abs(t) < std::abs(*turn)) turn = t;
  }
  return turn;
}

}  // namespace ephor::planner
