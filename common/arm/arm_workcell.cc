#include "common/arm/arm_workcell.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace ephor::arm {

namespace {

Eigen::Vector3d base_origin(const geometry::Workcell& cell) {
  return {cell.base_x_mm, cell.base_y_mm, cell.base_z_mm};
}

}  // namespace

Puma560 make_puma(const geometry::Workcell& cell) { return Puma560(cell.tool_length_mm); }

Eigen::Isometry3d tool_down_pose(const geometry::Workcell& cell, double x_mm, double y_mm,
                                 double z_mm, double theta_rad) {
  const Eigen::Vector3d z_tool(0.0, 0.0, -1.0);
  const Eigen::Vector3d x_tool(std::cos(theta_rad), std::sin(theta_rad), 0.0);
  Eigen::Matrix3d r;
  r.col(0) = x_tool;
  r.col(1) = z_tool.cross(x_tool);
  r.col(2) = z_tool;
  Eigen::Isometry3d in_field = Eigen::Isometry3d::Identity();
  in_field.linear() = r;
  in_field.translation() = Eigen::Vector3d(x_mm, y_mm, z_mm);
  return field_to_base(cell, in_field);
}

Eigen::Isometry3d base_pose(const geometry::Workcell& cell) {
  Eigen::Isometry3d b = Eigen::Isometry3d::Identity();
  b.linear() = Eigen::AngleAxisd(cell.base_yaw_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  b.translation() = base_origin(cell);
  return b;
}

Eigen::Isometry3d base_to_field(const geometry::Workcell& cell, const Eigen::Isometry3d& in_base) {
  return base_pose(cell) * in_base;
}

Eigen::Isometry3d field_to_base(const geometry::Workcell& cell, const Eigen::Isometry3d& in_field) {
  return base_pose(cell).inverse() * in_field;
}

Eigen::Vector3d base_point_to_field(const geometry::Workcell& cell, const Eigen::Vector3d& p) {
  return base_pose(cell) * p;
}

ToolInField tool_in_field(const geometry::Workcell& cell, const Joints& q) {
  // Tool length from the work cell, not from a Puma560 instance, so callers
  // need only the cell.
  const Eigen::Isometry3d in_base = make_puma(cell).forward(q);
  const Eigen::Isometry3d in_field = base_to_field(cell, in_base);
  const Eigen::Vector3d x_tool = in_field.linear().col(0);
  const Eigen::Vector3d z_tool = in_field.linear().col(2);
  ToolInField t;
  t.tip_mm = in_field.translation();
  t.theta_rad = std::atan2(x_tool.y(), x_tool.x());
  t.tilt_rad = std::acos(std::clamp(-z_tool.z(), -1.0, 1.0));
  return t;
}

bool reachable_tool_down(const geometry::Workcell& cell, double x_mm, double y_mm, double z_mm,
                         double theta_rad) {
  return !make_puma(cell).inverse(tool_down_pose(cell, x_mm, y_mm, z_mm, theta_rad)).empty();
}

double distance_from_column_mm(const geometry::Workcell& cell, double x_mm, double y_mm) {
  return std::hypot(x_mm - cell.base_x_mm, y_mm - cell.base_y_mm);
}

Joints reference_joints() {
  Joints q;
  q << 0.0, 0.35, -2.3, 0.0, -0.6, 0.0;
  return q;
}

Eigen::Vector3d park_point_mm(const geometry::Workcell& cell) {
  return {cell.field_length_mm - 60.0, 60.0, cell.elevation_plane_z_mm};
}

Joints park_joints(const geometry::Workcell& cell) {
  const Eigen::Vector3d p = park_point_mm(cell);
  const auto q = make_puma(cell).nearest_inverse(tool_down_pose(cell, p.x(), p.y(), p.z(), 0.0),
                                                 reference_joints());
  if (!q) {
    throw std::runtime_error("park pose (" + std::to_string(p.x()) + ", " + std::to_string(p.y()) +
                             ", " + std::to_string(p.z()) + ") mm of F is out of the PUMA's reach");
  }
  return *q;
}

}  // namespace ephor::arm
