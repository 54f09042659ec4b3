#include "common/motion/arm_collision_checker.h"

#include <numbers>

#include <gtest/gtest.h>

#include "common/arm/arm_workcell.h"

namespace ephor::arm {
namespace {

TEST(ArmCollisionCheckerTest, ParkAndWorkingPosesAreClear) {
  const geometry::Workcell cell;
  const Puma560 arm = make_puma(cell);
  const ArmCollisionChecker checker(arm, cell);
  EXPECT_TRUE(checker.clear(park_joints(cell)));
  const auto q = arm.nearest_inverse(
      tool_down_pose(cell, 100.0, 100.0, cell.object_plane_z_mm, 0.0), reference_joints());
  ASSERT_TRUE(q);
  EXPECT_TRUE(checker.clear(*q)) << *checker.collision(*q);
  EXPECT_FALSE(
      checker.clear(*q, cell.object_plane_z_mm + 10.0));  // lowest tip height for the motion
}

TEST(ArmCollisionCheckerTest, TableAndPedestalCollide) {
  const geometry::Workcell cell;
  const Puma560 arm = make_puma(cell);
  const ArmCollisionChecker checker(arm, cell);
  // Tip 5 mm below the table.
  const auto low =
      arm.nearest_inverse(tool_down_pose(cell, 100.0, 100.0, -5.0, 0.0), reference_joints());
  ASSERT_TRUE(low);
  const auto why = checker.collision(*low);
  ASSERT_TRUE(why);
  EXPECT_NE(why->find("table"), std::string::npos) << *why;
  // Upper arm pointing steeply down along the pedestal.
  Joints down = Joints::Zero();
  down[1] = -75.0 * std::numbers::pi / 180.0;
  const auto ped = checker.collision(down);
  ASSERT_TRUE(ped);
  EXPECT_NE(ped->find("pedestal"), std::string::npos) << *ped;
  EXPECT_TRUE(checker.collision(Joints::Constant(std::nan(""))));
}

}  // namespace
}  // namespace ephor::arm
