#include "common/shepherd/sim/simulator.h"

#include <cmath>

#include <gtest/gtest.h>

#include "common/arm/arm_workcell.h"

namespace ephor::sim {
namespace {

SimulatorConfig quiet_field() {
  SimulatorConfig c;
  c.world.sheep = 0;
  c.world.wander_rad_s = 0.0;
  return c;
}

// A joint move from the arm's current pose to the tool down at (x, y, z) of F.
JointTrajectory move_tool(const Simulator& sim, int64_t seq, double x, double y, double z,
                          double duration_s) {
  const auto& cell = sim.config().world.workcell;
  const auto goal =
      sim.puma().nearest_inverse(arm::tool_down_pose(cell, x, y, z, 0.0), sim.servo().q);
  EXPECT_TRUE(goal.has_value()) << "unreachable (" << x << ", " << y << ", " << z << ")";
  JointTrajectory t;
  t.seq = seq;
  t.t_s = {duration_s};
  t.q = {goal.value_or(sim.servo().q)};
  t.qd = {arm::Joints::Zero()};
  return t;
}

int bright_pixels_near(const std::vector<uint8_t>& img, const Eigen::Vector2d& c, double r) {
  int n = 0;
  for (int v = 0; v < 482; ++v)
    for (int u = 0; u < 512; ++u)
      if ((Eigen::Vector2d(u, v) - c).norm() < r &&
          img[static_cast<size_t>(v) * 512 + static_cast<size_t>(u)] > 180)
        ++n;
  return n;
}

TEST(Simulator, ArmStartsParkedInTheElevationPlane) {
  SimulatorConfig c;
  c.world.sheep = 6;
  Simulator sim(c);
  const auto& cell = c.world.workcell;
  EXPECT_NEAR(sim.tool_tip_mm().z(), cell.elevation_plane_z_mm, 1.0);
  EXPECT_LT((sim.tool_tip_mm() - arm::park_point_mm(cell)).norm(), 1.0);
  EXPECT_TRUE(sim.servo().trajectory_done);
  EXPECT_FALSE(sim.servo().fault);
}

TEST(Simulator, LoweredArmOverASheepTurnsItAndHidesItsMark) {
  Simulator sim(quiet_field());
  const auto& cell = sim.config().world.workcell;
  // A standing sheep heading out of the field, away from the arm's park corner.
  const int32_t id = sim.world().add_sheep(300.0, 250.0, -2.0, 0.0);
  std::vector<uint8_t> img;
  auto gt = sim.render(img);
  ASSERT_EQ(gt.sheep.size(), 1u);
  EXPECT_TRUE(gt.sheep[0].view.visible);
  EXPECT_GT(bright_pixels_near(img, gt.sheep[0].view.centre_px, 12.0), 150);

  // Over it in the elevation plane: hidden, not touched.
  ASSERT_TRUE(sim.follow(
      move_tool(sim, 1, 300.0, 250.0, cell.elevation_plane_z_mm,
                6.0)));  // one joint-space step from park: slow enough for the joint speed limits
  for (int i = 0; i < 80 && !sim.servo().trajectory_done; ++i) sim.step(0.1);
  ASSERT_TRUE(sim.servo().trajectory_done);
  ASSERT_FALSE(sim.servo().fault) << sim.servo().fault_reason;
  gt = sim.render(img);
  EXPECT_FALSE(gt.sheep[0].view.visible);
  EXPECT_EQ(bright_pixels_near(img, gt.sheep[0].view.centre_px, 12.0), 0);
  EXPECT_EQ(sim.world().saves(), 0);

  // Lowered into the object plane: touched, turned the way the tool faces
  // (theta 0, move_tool: +x of F, as the arm's forward kinematics say).
  ASSERT_TRUE(sim.follow(move_tool(sim, 2, 300.0, 250.0, cell.object_plane_z_mm, 2.0)));
  for (int i = 0; i < 30 && !sim.servo().trajectory_done; ++i) sim.step(0.1);
  EXPECT_EQ(sim.world().saves(), 1);
  const auto s = sim.world().sheep();
  ASSERT_EQ(s.size(), 1u);
  EXPECT_EQ(s[0].id, id);
  const double tool_theta = arm::tool_in_field(cell, sim.servo().q).theta_rad;
  EXPECT_NEAR(tool_theta, 0.0, 1e-3);
  EXPECT_NEAR(std::remainder(s[0].body_angle_rad - tool_theta, 2 * M_PI), 0.0, 0.01);
  gt = sim.render(img);
  EXPECT_FALSE(gt.sheep[0].view.visible);
}

TEST(Simulator, ToolLightShinesAtTheTipOverTheArm) {
  Simulator sim(quiet_field());
  const auto& cell = sim.config().world.workcell;
  const auto& cam = sim.config().camera.camera;
  // Tool lowered at a point where the wrist and links lie over the tip in the image.
  ASSERT_TRUE(sim.follow(move_tool(sim, 1, 400.0, 300.0, cell.object_plane_z_mm, 4.0)));
  for (int i = 0; i < 60 && !sim.servo().trajectory_done; ++i) sim.step(0.1);
  ASSERT_TRUE(sim.servo().trajectory_done);
  const Eigen::Vector3d tip = sim.tool_tip_mm();
  const Eigen::Vector2d at = cam.project(tip.x(), tip.y(), tip.z());

  std::vector<uint8_t> dark, lit;
  EXPECT_FALSE(sim.tool_light());
  sim.render(dark);
  EXPECT_EQ(bright_pixels_near(dark, at, 10.0), 0) << "no light, only the dark arm at the tip";

  sim.set_tool_light(true);
  sim.render(lit);
  // A disc of radius 6 px (~113 px^2), as bright as a wool mark, centred on the tip.
  const int n = bright_pixels_near(lit, at, 10.0);
  EXPECT_GT(n, 90);
  EXPECT_LT(n, 140);
  double sw = 0.0, su = 0.0, sv = 0.0;
  uint8_t peak = 0;
  for (int v = 0; v < 482; ++v)
    for (int u = 0; u < 512; ++u) {
      const size_t i = static_cast<size_t>(v) * 512 + static_cast<size_t>(u);
      const double d = static_cast<double>(lit[i]) - static_cast<double>(dark[i]);
      if ((Eigen::Vector2d(u, v) - at).norm() > 10.0) {
        EXPECT_LT(std::abs(d), 25.0)
            << "light changed a pixel away from the tip at " << u << ", " << v;
        continue;
      }
      peak = std::max(peak, lit[i]);
      sw += d;
      su += d * u;
      sv += d * v;
    }
  EXPECT_GE(peak, 230);
  EXPECT_LT((Eigen::Vector2d(su / sw, sv / sw) - at).norm(), 0.1);

  sim.set_tool_light(false);
  sim.render(lit);
  EXPECT_EQ(bright_pixels_near(lit, at, 10.0), 0);
}

TEST(Simulator, SameSeedSameFramesAndTruth) {
  SimulatorConfig c;
  c.world.sheep = 5;
  c.world.seed = 9;
  Simulator a(c), b(c);
  std::vector<uint8_t> ia, ib;
  for (int k = 0; k < 5; ++k) {
    a.step(0.4);
    b.step(0.4);
    const auto ga = a.render(ia), gb = b.render(ib);
    ASSERT_EQ(ia, ib);
    ASSERT_EQ(ga.sheep.size(), gb.sheep.size());
    for (size_t i = 0; i < ga.sheep.size(); ++i) {
      EXPECT_EQ(ga.sheep[i].state.centre_mm, gb.sheep[i].state.centre_mm);
      EXPECT_EQ(ga.sheep[i].view.centre_px, gb.sheep[i].view.centre_px);
    }
  }
}

}  // namespace
}  // namespace ephor::sim
