#pragma once
// The PUMA 560 in the work cell: poses of the tool in the field frame F (mm)
// converted to and from the arm's base frame, the park pose, and what the
// paper's two working planes mean for the arm.
//
// The base frame's origin is at (base_x, base_y, base_z) of F and its axes are
// parallel to F's (workcell.h), so a pose in F becomes a base-frame pose by a
// translation only.
//
// "Tool down with orientation theta": the approach axis z_tool points along
// -z of F; the manipulator's orientation x_tool = (cos theta, sin theta, 0) in
// F, theta in rad about +z of F.
//
// Reach (measured by arm_workcell_test): the PUMA's shoulder offset
// (d3 = 150.05 mm) keeps the wrist centre at least d3 from the column axis, so
// with the tool vertical the tip cannot reach a disc of radius ~d3 around the
// column (the pedestal at the field centre). In the elevation plane the wrist
// is only 150 mm below the shoulder and the elbow limit keeps it >= ~311 mm
// from the shoulder: that plane is reachable only from ~345 mm out. The object
// plane is reachable from d3 + 10 mm out to the corners. Straight moves across
// the centre in the elevation plane therefore need a joint-space path.

#include <optional>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "common/arm/puma560.h"
#include "common/geometry/workcell.h"

namespace ephor::arm {

// A tool-down pose in F: tip position (mm) and manipulator orientation (rad).
struct ToolInField {
  Eigen::Vector3d tip_mm;  // tool tip in F, mm
  double theta_rad;        // orientation of x_tool about +z of F, rad (atan2 of its xy)
  double tilt_rad;         // angle between the approach axis and -z of F, rad (0 = straight down)
};

// The PUMA with the work cell's tool length.
Puma560 make_puma(const geometry::Workcell& cell);

// Tool down at (x, y, z) of F with orientation theta -> tool pose in the base frame (mm).
Eigen::Isometry3d tool_down_pose(const geometry::Workcell& cell, double x_mm, double y_mm,
                                 double z_mm, double theta_rad);

// The base frame in F: the column axis at (base_x, base_y, base_z), turned
// by base_yaw about z.
Eigen::Isometry3d base_pose(const geometry::Workcell& cell);
// Base-frame pose <-> F pose.
Eigen::Isometry3d base_to_field(const geometry::Workcell& cell, const Eigen::Isometry3d& in_base);
Eigen::Isometry3d field_to_base(const geometry::Workcell& cell, const Eigen::Isometry3d& in_field);
// A point of the base frame (e.g. a link origin) in F, mm.
Eigen::Vector3d base_point_to_field(const geometry::Workcell& cell, const Eigen::Vector3d& p);

// Where the tool is in F for joints q.
ToolInField tool_in_field(const geometry::Workcell& cell, const Joints& q);

// True when the tool, pointing down with orientation theta, can be at
// (x, y, z) of F within the joint limits (any IK branch). For planners that
// must not choose an intercept the arm cannot reach.
bool reachable_tool_down(const geometry::Workcell& cell, double x_mm, double y_mm, double z_mm,
                         double theta_rad = 0.0);

// Distance of (x, y) of F from the column axis, mm.
double distance_from_column_mm(const geometry::Workcell& cell, double x_mm, double y_mm);

// Park: tool down in the elevation plane above the field's lower-right corner
// (x = field_length - 60 mm, y = 60 mm), theta = 0, so the arm hides little
// of the field. Elbow-up configuration nearest qz-like pose. Throws
// std::runtime_error if the work cell makes the corner unreachable.
Joints park_joints(const geometry::Workcell& cell);

// Point of F where park_joints puts the tool tip.
Eigen::Vector3d park_point_mm(const geometry::Workcell& cell);

// Reference pose used to choose among IK branches when nothing better is known:
// shoulder "right", elbow up, wrist not flipped, arm over the field.
Joints reference_joints();

}  // namespace ephor::arm
