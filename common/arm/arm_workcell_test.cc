#include "common/arm/arm_workcell.h"

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

namespace ephor::arm {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kElevationMinRadiusMm = 350.0;
constexpr double kObjectMinRadiusMm = Puma560::kD3Mm + 10.0;

TEST(ArmWorkcellTest, ToolDownPoseRoundTripsThroughInverseAndToolInField) {
  const geometry::Workcell cell;
  const Puma560 arm = make_puma(cell);
  const auto q = arm.nearest_inverse(
      tool_down_pose(cell, 100.0, 800.0, cell.object_plane_z_mm, 0.7), reference_joints());
  ASSERT_TRUE(q.has_value());
  const ToolInField t = tool_in_field(cell, *q);
  EXPECT_LT((t.tip_mm - Eigen::Vector3d(100.0, 800.0, cell.object_plane_z_mm)).norm(), 1e-6);
  EXPECT_NEAR(t.theta_rad, 0.7, 1e-9);
  EXPECT_NEAR(t.tilt_rad, 0.0, 1e-6);
}

// The paper's arm works anywhere on the field in both planes. With the tool
// vertical the PUMA cannot reach within d3 of its column (the pedestal and a
// ring around it at the field centre). In the elevation plane the wrist is only
// 150 mm below the shoulder, and the elbow limit (q3 >= -225 deg) keeps the
// wrist >= ~311 mm from the shoulder: that plane is reachable from about
// 345 mm out (measured by this test). Everything else must be reachable, for any orientation, and
// every solution must reproduce the pose.
TEST(ArmWorkcellTest, EveryFieldPointOutsideTheColumnRingIsReachableWithTheToolDown) {
  const geometry::Workcell cell;
  const Puma560 arm = make_puma(cell);
  int reachable = 0, unreachable_ring = 0;
  for (double z : {cell.object_plane_z_mm, cell.elevation_plane_z_mm}) {
    for (double x = 0.0; x <= cell.field_length_mm + 1e-9; x += cell.field_length_mm / 24.0) {
      for (double y = 0.0; y <= cell.field_width_mm + 1e-9; y += cell.field_width_mm / 18.0) {
        for (double theta : {-kPi, -kPi / 2, 0.0, kPi / 4, kPi / 2}) {
          const Eigen::Isometry3d pose = tool_down_pose(cell, x, y, z, theta);
          const auto solutions = arm.inverse(pose);
          for (const Joints& s : solutions) {
            const Eigen::Isometry3d back = arm.forward(s);
            EXPECT_LT((back.translation() - pose.translation()).norm(), 1e-6);
            EXPECT_LT((back.linear() - pose.linear()).cwiseAbs().maxCoeff(), 1e-9);
          }
          const double r = distance_from_column_mm(cell, x, y);
          const double r_min =
              z > cell.object_plane_z_mm ? kElevationMinRadiusMm : kObjectMinRadiusMm;
          if (r > r_min) {
            EXPECT_FALSE(solutions.empty())
                << "(" << x << ", " << y << ", " << z << ") theta " << theta;
            ++reachable;
          } else if (r < Puma560::kD3Mm - 1.0) {
            EXPECT_TRUE(solutions.empty());
            ++unreachable_ring;
          }
        }
      }
    }
  }
  EXPECT_GT(reachable, 3000);
  EXPECT_TRUE(reachable_tool_down(cell, 100.0, 100.0, cell.object_plane_z_mm));
  EXPECT_FALSE(
      reachable_tool_down(cell, cell.base_x_mm, cell.base_y_mm + 200.0, cell.elevation_plane_z_mm));
  EXPECT_GT(unreachable_ring, 0);
}

TEST(ArmWorkcellTest, ParkIsToolDownAboveLowerRightCornerInElevationPlane) {
  const geometry::Workcell cell;
  const Joints q = park_joints(cell);
  EXPECT_TRUE(make_puma(cell).limits().within(q));
  const ToolInField t = tool_in_field(cell, q);
  EXPECT_NEAR(t.tip_mm.x(), cell.field_length_mm - 60.0, 1e-6);
  EXPECT_NEAR(t.tip_mm.y(), 60.0, 1e-6);
  EXPECT_NEAR(t.tip_mm.z(), cell.elevation_plane_z_mm, 1e-6);
  EXPECT_NEAR(t.tilt_rad, 0.0, 1e-6);
}

// A turned base (Workcell::base_yaw_rad): a tool-down pose of F solved in the
// base frame comes back to the same point and orientation of F, and joint 1
// turns by the yaw difference for the same point.
TEST(ArmWorkcellTest, TurnedBaseRoundTripsToolPosesThroughTheBaseFrame) {
  geometry::Workcell turned;
  turned.base_yaw_rad = 1.2;
  const Puma560 puma = make_puma(turned);
  const double x = 300.0, y = 250.0, z = turned.elevation_plane_z_mm, theta = 0.4;
  const auto q = puma.nearest_inverse(tool_down_pose(turned, x, y, z, theta), reference_joints());
  ASSERT_TRUE(q.has_value());
  const ToolInField t = tool_in_field(turned, *q);
  EXPECT_NEAR(t.tip_mm.x(), x, 1e-6);
  EXPECT_NEAR(t.tip_mm.y(), y, 1e-6);
  EXPECT_NEAR(t.tip_mm.z(), z, 1e-6);
  EXPECT_NEAR(t.theta_rad, theta, 1e-9);
  EXPECT_NEAR(t.tilt_rad, 0.0, 1e-6);
  EXPECT_NEAR((base_point_to_field(turned, Eigen::Vector3d::Zero()) -
               Eigen::Vector3d(turned.base_x_mm, turned.base_y_mm, turned.base_z_mm))
                  .norm(),
              0.0, 1e-9);

  // The same configuration under an unturned base: joint 1 differs by the yaw.
  const geometry::Workcell straight;
  Joints seed = *q;
  seed(0) += 1.2;
  const auto q0 = puma.nearest_inverse(tool_down_pose(straight, x, y, z, theta), seed);
  ASSERT_TRUE(q0.has_value());
  EXPECT_NEAR(std::remainder((*q0)(0) - (*q)(0), 2.0 * std::numbers::pi), 1.2, 1e-6);
  EXPECT_NEAR(((*q0).tail<5>() - (*q).tail<5>()).norm(), 0.0, 1e-6);
}

}  // namespace
}  // namespace ephor::arm
