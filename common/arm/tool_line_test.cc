#include "common/arm/tool_line.h"

#include <cmath>

#include <gtest/gtest.h>

#include "common/arm/arm_workcell.h"

namespace ephor::arm {
namespace {

// Joints with the tool down at (x, y) of the elevation plane, nearest the park pose.
Joints joints_at(const geometry::Workcell& cell, const Puma560& arm, double x, double y) {
  const auto q = arm.nearest_inverse(tool_down_pose(cell, x, y, cell.elevation_plane_z_mm, 0.0),
                                     park_joints(cell));
  EXPECT_TRUE(q.has_value());
  return q.value_or(Joints::Zero());
}

TEST(ToolLineTest, PosesAlongTheLineAreLinearInPositionAndSlerpInOrientation) {
  const geometry::Workcell cell;
  const Eigen::Isometry3d a = tool_down_pose(cell, 1000.0, 100.0, 200.0, 0.0);
  const Eigen::Isometry3d b = tool_down_pose(cell, 1000.0, 400.0, 120.0, 1.0);
  const ToolLine line(a, b);
  EXPECT_NEAR(line.length_mm(), std::hypot(300.0, 80.0), 1e-9);
  EXPECT_NEAR(line.angle_rad(), 1.0, 1e-9);
  EXPECT_LT((line.at(0.0).translation() - a.translation()).norm(), 1e-9);
  EXPECT_LT((line.at(1.0).translation() - b.translation()).norm(), 1e-9);
  EXPECT_LT((line.at(0.5).translation() - 0.5 * (a.translation() + b.translation())).norm(), 1e-9);
  // Half way the tool has turned half the angle about the vertical.
  const Eigen::Quaterniond r0(a.linear()), rh(line.at(0.5).linear());
  EXPECT_NEAR(r0.angularDistance(rh), 0.5, 1e-9);
  EXPECT_LT((line.at(2.0).translation() - b.translation()).norm(), 1e-9);  // clamped
}

TEST(ToolLineTest, AShortMoveIsFollowedToTheGoalInOneBranch) {
  const geometry::Workcell cell;
  const Puma560 arm = make_puma(cell);
  const Joints start = joints_at(cell, arm, 1100.0, 150.0);
  const Eigen::Isometry3d goal = tool_down_pose(cell, 1100.0, 350.0, cell.object_plane_z_mm, 0.3);
  Joints end = Joints::Zero();
  int samples_seen = 0;
  const auto stop = ToolLine(arm.forward(start), goal)
                        .follow(
                            arm, start, 50, 0.1,
                            [&](const Joints&) {
                              ++samples_seen;
                              return true;
                            },
                            &end);
  EXPECT_FALSE(stop.has_value());
  EXPECT_EQ(samples_seen, 50);
  EXPECT_LT((end - *arm.nearest_inverse(goal, start)).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT((arm.forward(end).translation() - goal.translation()).norm(), 1e-6);
}

TEST(ToolLineTest, ALineOutOfReachBreaksWhereTheReachEnds) {
  const geometry::Workcell cell;
  const Puma560 arm = make_puma(cell);
  const Joints start = joints_at(cell, arm, 1100.0, 457.0);
  // 2 m beyond the field's right edge: the arm reaches about 0.86 m.
  const auto stop = ToolLine(arm.forward(start),
                             tool_down_pose(cell, 3100.0, 457.0, cell.elevation_plane_z_mm, 0.0))
                        .follow(arm, start, 100, 10.0);  // no jump limit: only reach
  ASSERT_TRUE(stop.has_value());
  EXPECT_EQ(stop->kind, LineBreak::Kind::kUnreachable);
  // The tool starts 490 mm from the column and reaches about 370 mm further.
  EXPECT_GT(stop->u, 0.1);
  EXPECT_LT(stop->u, 0.3);
}

TEST(ToolLineTest, ALineAcrossTheColumnBreaksWithAJointJump) {
  const geometry::Workcell cell;
  const Puma560 arm = make_puma(cell);
  // Left edge to right edge through the field centre, in the object plane
  // (reachable to d3 + 10 mm from the column): joint 1 must flip round.
  const Joints start = *arm.nearest_inverse(
      tool_down_pose(cell, 150.0, 457.0, cell.object_plane_z_mm, 0.0), park_joints(cell));
  const auto stop =
      ToolLine(arm.forward(start), tool_down_pose(cell, 1069.0, 457.0, cell.object_plane_z_mm, 0.0))
          .follow(arm, start, 400, 0.5);
  ASSERT_TRUE(stop.has_value());
  EXPECT_NE(stop->kind, LineBreak::Kind::kRejected);
  if (stop->kind == LineBreak::Kind::kJump) {
    EXPECT_GT(stop->jump_rad, 0.5);
  }
  EXPECT_GT(stop->u, 0.2);
  EXPECT_LT(stop->u, 0.8);
}

TEST(ToolLineTest, ARejectedSampleStopsTheWalkThere) {
  const geometry::Workcell cell;
  const Puma560 arm = make_puma(cell);
  const Joints start = joints_at(cell, arm, 1100.0, 150.0);
  const Eigen::Isometry3d goal = tool_down_pose(cell, 1100.0, 350.0, 200.0, 0.0);
  int calls = 0;
  const auto stop =
      ToolLine(arm.forward(start), goal).follow(arm, start, 10, 0.1, [&](const Joints&) {
        return ++calls < 4;
      });
  ASSERT_TRUE(stop.has_value());
  EXPECT_EQ(stop->kind, LineBreak::Kind::kRejected);
  EXPECT_NEAR(stop->u, 0.4, 1e-12);
  EXPECT_EQ(calls, 4);
}

}  // namespace
}  // namespace ephor::arm
