#include "common/shepherd/sim/world.h"

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

namespace ephor::sim {
namespace {

constexpr double kPi = std::numbers::pi;

WorldConfig empty_field() {
  WorldConfig c;
  c.sheep = 0;
  c.wander_rad_s = 0.0;
  return c;
}

const SheepState* find(const std::vector<SheepState>&& all, int32_t id) = delete;  // dangling
const SheepState* find(const std::vector<SheepState>& all, int32_t id) {
  for (const auto& s : all)
    if (s.id == id) return &s;
  return nullptr;
}

TEST(World, SheepDriveStraightAtTheirOwnSpeed) {
  World world(empty_field());
  struct Start {
    double x, y, heading, speed;
  };
  const Start starts[] = {{300, 200, 0.3, 30.0}, {900, 700, -2.5, 24.0}, {300, 700, -1.2, 36.0}};
  std::vector<int32_t> ids;
  for (const auto& s : starts) ids.push_back(world.add_sheep(s.x, s.y, s.heading, s.speed));
  const double duration = 8.0;
  for (int i = 0; i < 800; ++i) world.step(0.01);
  const auto now = world.sheep();
  for (size_t i = 0; i < ids.size(); ++i) {
    const SheepState* s = find(now, ids[i]);
    ASSERT_NE(s, nullptr);
    const Eigen::Vector2d dir(std::cos(starts[i].heading), std::sin(starts[i].heading));
    const Eigen::Vector2d moved = s->centre_mm - Eigen::Vector2d(starts[i].x, starts[i].y);
    EXPECT_NEAR(moved.dot(dir), starts[i].speed * duration, 0.5) << "sheep " << ids[i];
    EXPECT_NEAR(moved.x() * dir.y() - moved.y() * dir.x(), 0.0, 0.5) << "drifted sideways";
    EXPECT_NEAR(s->speed_mm_s(), starts[i].speed, 0.05);
    EXPECT_NEAR(std::remainder(s->heading_rad() - starts[i].heading, 2 * kPi), 0.0, 1e-3);
  }
}

TEST(World, SpeedsSpreadAroundTheNominalSpeed) {
  WorldConfig c;
  c.sheep = 8;
  c.seed = 3;
  World world(c);
  const auto herd = world.sheep();
  ASSERT_EQ(herd.size(), 8u);
  double lo = 1e9, hi = 0.0;
  for (const auto& s : herd) {  // the paper's 8 mm/s +- 20 %
    EXPECT_GE(s.drive_speed_mm_s, 6.4);
    EXPECT_LE(s.drive_speed_mm_s, 9.6);
    EXPECT_TRUE(s.on_field);
    lo = std::min(lo, s.drive_speed_mm_s);
    hi = std::max(hi, s.drive_speed_mm_s);
  }
  EXPECT_GT(hi - lo, 0.5) << "every sheep got the same speed";
}

TEST(World, WanderBendsThePathSlowly) {
  WorldConfig c = empty_field();
  c.wander_rad_s = 0.05;
  World world(c);
  const int32_t id = world.add_sheep(300, 200, 0.0, 30.0);
  for (int i = 0; i < 500; ++i) world.step(0.01);
  const auto herd = world.sheep();
  const SheepState* s = find(herd, id);
  ASSERT_NE(s, nullptr);
  EXPECT_GT(std::abs(s->centre_mm.y() - 200.0), 0.01) << "no wander at all";
  EXPECT_LT(std::abs(s->heading_rad()), 1.0) << "wander is not slow";
}

TEST(World, CollidingSheepStayApart) {
  World world(empty_field());
  // Head on, slightly offset, fast so that they hit hard; and one into the pedestal.
  const int32_t a = world.add_sheep(250, 200, 0.0, 80.0);
  const int32_t b = world.add_sheep(650, 230, kPi, 80.0);
  const int32_t c = world.add_sheep(350, 457, 0.0, 80.0);
  double deepest = 0.0;
  double min_gap_to_column = 1e9;
  double closest_ab = 1e9;
  bool met = false;
  const auto& cell = world.config().workcell;
  for (int i = 0; i < 1000; ++i) {
    world.step(0.005);
    deepest = std::max(deepest, world.deepest_penetration_mm());
    const auto herd = world.sheep();
    const SheepState* sa = find(herd, a);
    const SheepState* sb = find(herd, b);
    if (sa && sb && (sa->centre_mm - sb->centre_mm).norm() < 240.0) met = true;
    if (sa && sb) closest_ab = std::min(closest_ab, (sa->centre_mm - sb->centre_mm).norm());
    for (const auto& s : herd)
      min_gap_to_column =
          std::min(min_gap_to_column,
                   (s.centre_mm - Eigen::Vector2d(cell.base_x_mm, cell.base_y_mm)).norm());
  }
  EXPECT_TRUE(met) << "the two sheep never came close";
  // Woolled sheep bounce: after the collision they drive apart, and the one
  // that drove into the pedestal drives away from it - nobody stays stuck.
  const auto herd = world.sheep();
  const SheepState* sa = find(herd, a);
  const SheepState* sb = find(herd, b);
  const SheepState* sc = find(herd, c);
  ASSERT_TRUE(sa && sb && sc);
  EXPECT_GT((sa->centre_mm - sb->centre_mm).norm(), closest_ab + 100.0);
  EXPECT_GT((sc->centre_mm - Eigen::Vector2d(cell.base_x_mm, cell.base_y_mm)).norm(),
            min_gap_to_column + 100.0);
  for (const auto* s : {sa, sb, sc}) EXPECT_NEAR(s->speed_mm_s(), 80.0, 1.0);
  EXPECT_LT(deepest, 3.0) << "bodies overlapped by " << deepest << " mm";
  // Half a body width plus the column radius, less the allowed overlap.
  EXPECT_GT(min_gap_to_column, cell.pedestal_radius_mm + 0.5 * 89.0 - 3.0);
}

// Issue 13's switches: with collisions off, sheep pass through each other
// (and with the pedestal off, through the column) without turning.
TEST(World, SwitchedOffCollisionsLetSheepPassThrough) {
  WorldConfig c = empty_field();
  c.sheep_collisions = false;
  c.pedestal = false;
  World world(c);
  const int32_t a = world.add_sheep(250, 200, 0.0, 80.0);
  const int32_t b = world.add_sheep(650, 200, kPi, 80.0);
  const int32_t d = world.add_sheep(350, 457, 0.0, 80.0);  // straight at the column
  for (int i = 0; i < 600; ++i) world.step(0.005);         // 3 s: 240 mm each
  const auto herd = world.sheep();
  const SheepState* sa = find(herd, a);
  const SheepState* sb = find(herd, b);
  const SheepState* sd = find(herd, d);
  ASSERT_TRUE(sa && sb && sd);
  EXPECT_NEAR(sa->centre_mm.x(), 490.0, 1.0);  // passed b's start line unturned
  EXPECT_NEAR(sb->centre_mm.x(), 410.0, 1.0);
  EXPECT_NEAR(sd->centre_mm.x(), 590.0, 1.0);  // through the column at (609.5, 457)
  EXPECT_NEAR(sa->velocity_mm_s.x(), 80.0, 0.5);
  EXPECT_NEAR(sd->velocity_mm_s.y(), 0.0, 0.5);
}

TEST(World, EscapedSheepIsCountedAndReentersWithANewId) {
  WorldConfig c = empty_field();
  c.reentry_s = 1.0;
  World world(c);
  const int32_t id = world.add_sheep(60, 457, kPi, 30.0);  // 2 s from the left edge
  double escaped_at = -1.0;
  for (int i = 0; i < 400 && escaped_at < 0.0; ++i) {
    world.step(0.01);
    if (world.escapes() == 1) escaped_at = world.time_s();
  }
  ASSERT_GT(escaped_at, 0.0);
  EXPECT_NEAR(escaped_at, 2.0, 0.05);
  EXPECT_TRUE(world.sheep().empty());
  while (world.time_s() < escaped_at + 0.95) world.step(0.01);
  EXPECT_TRUE(world.sheep().empty()) << "re-entered before the delay";
  while (world.time_s() < escaped_at + 1.05) world.step(0.01);
  const auto herd = world.sheep();
  ASSERT_EQ(herd.size(), 1u);
  EXPECT_NE(herd[0].id, id);
  EXPECT_TRUE(herd[0].on_field);
  // Heading inward: after a second it is farther from the nearest edge (at
  // least 8 mm/s x cos(entry_angle 0.8 rad) x 20 % spread, about 3.6 mm).
  const auto edge_distance = [&](const SheepState& s) {
    return std::min(
        {s.centre_mm.x(), s.centre_mm.y(), 1219.0 - s.centre_mm.x(), 914.0 - s.centre_mm.y()});
  };
  const double d0 = edge_distance(herd[0]);
  EXPECT_LT(d0, 5.0);  // entered at the edge a few steps ago
  for (int i = 0; i < 100; ++i) world.step(0.01);
  ASSERT_EQ(world.sheep().size(), 1u);
  EXPECT_GT(edge_distance(world.sheep()[0]), d0 + 3.0);
  EXPECT_EQ(world.escapes(), 1);
}

TEST(World, NegativeReentryDelayMeansGoneForGood) {
  WorldConfig c = empty_field();
  c.reentry_s = -1.0;
  World world(c);
  world.add_sheep(1200, 457, 0.0, 30.0);
  for (int i = 0; i < 300; ++i) world.step(0.05);
  EXPECT_EQ(world.escapes(), 1);
  EXPECT_TRUE(world.sheep().empty());
}

TEST(World, LoweredToolTurnsTheSheepTowardTheCentre) {
  World world(empty_field());
  const auto& cell = world.config().workcell;
  const int32_t id = world.add_sheep(250, 200, kPi, 30.0);  // heading for the left edge
  // Tool in the elevation plane above it: no effect.
  world.set_tool_tip(Eigen::Vector3d(250, 200, cell.elevation_plane_z_mm));
  world.step(0.1);
  EXPECT_EQ(world.saves(), 0);
  // Lowered to the object plane on its body (near its tail): turned, one save.
  world.set_tool_tip(Eigen::Vector3d(280, 210, cell.object_plane_z_mm));
  for (int i = 0; i < 20; ++i) world.step(0.01);
  EXPECT_EQ(world.saves(), 1) << "a touch counts once";
  world.set_tool_tip(Eigen::Vector3d(280, 210, cell.elevation_plane_z_mm));
  world.step(0.01);
  const auto herd = world.sheep();
  const SheepState* s = find(herd, id);
  ASSERT_NE(s, nullptr);
  const double to_centre =
      std::atan2(cell.centre_y_mm() - s->centre_mm.y(), cell.centre_x_mm() - s->centre_mm.x());
  EXPECT_NEAR(std::remainder(s->heading_rad() - to_centre, 2 * kPi), 0.0, 0.05);
  EXPECT_NEAR(s->speed_mm_s(), 30.0, 0.5);
  // A second touch is a second save; a tool beside the sheep is no touch.
  world.set_tool_tip(Eigen::Vector3d(s->centre_mm.x(), s->centre_mm.y(), cell.object_plane_z_mm));
  world.step(0.01);
  EXPECT_EQ(world.saves(), 2);
  world.set_tool_tip(Eigen::Vector3d(s->centre_mm.x() + 200.0, s->centre_mm.y(), 30.0));
  world.step(0.01);
  world.set_tool_tip(Eigen::Vector3d(s->centre_mm.x() + 200.0, s->centre_mm.y() + 5, 30.0));
  world.step(0.01);
  EXPECT_EQ(world.saves(), 2);
}

// The manipulator redirects the sheep the way it faces (the planner aims it
// past the pedestal); with its orientation unknown, or the switch off,
// toward the centre.
TEST(World, TouchedSheepGoesTheWayTheToolFaces) {
  for (const bool along_tool : {true, false}) {
    WorldConfig c = empty_field();
    c.touch_turns_along_tool = along_tool;
    World world(c);
    const auto& cell = world.config().workcell;
    const int32_t id = world.add_sheep(250, 200, kPi, 30.0);
    world.set_tool_tip(Eigen::Vector3d(280, 210, cell.object_plane_z_mm), 0.3);
    world.step(0.01);
    world.set_tool_tip(Eigen::Vector3d(280, 210, cell.elevation_plane_z_mm), 0.3);
    world.step(0.01);
    const auto herd = world.sheep();
    const SheepState* s = find(herd, id);
    ASSERT_NE(s, nullptr);
    const double expected = along_tool ? 0.3
                                       : std::atan2(cell.centre_y_mm() - s->centre_mm.y(),
                                                    cell.centre_x_mm() - s->centre_mm.x());
    EXPECT_NEAR(std::remainder(s->heading_rad() - expected, 2 * kPi), 0.0, 0.05)
        << "along_tool " << along_tool;
  }
}

TEST(World, SameSeedSameWorld) {
  WorldConfig c;
  c.sheep = 6;
  c.seed = 42;
  c.reentry_s = 1.0;
  World a(c), b(c);
  c.seed = 43;
  World other(c);
  for (int i = 0; i < 600; ++i) {
    a.step(0.02);
    b.step(0.02);
    other.step(0.02);
  }
  const auto sa = a.sheep(), sb = b.sheep(), so = other.sheep();
  ASSERT_EQ(sa.size(), sb.size());
  for (size_t i = 0; i < sa.size(); ++i) {
    EXPECT_EQ(sa[i].id, sb[i].id);
    EXPECT_EQ(sa[i].centre_mm, sb[i].centre_mm);
    EXPECT_EQ(sa[i].body_angle_rad, sb[i].body_angle_rad);
    EXPECT_EQ(sa[i].velocity_mm_s, sb[i].velocity_mm_s);
  }
  EXPECT_EQ(a.escapes(), b.escapes());
  EXPECT_NE(sa.front().centre_mm, so.front().centre_mm);
  // reset() replays the same world.
  a.reset(42);
  for (int i = 0; i < 600; ++i) a.step(0.02);
  EXPECT_EQ(a.sheep().front().centre_mm, sb.front().centre_mm);
}

TEST(World, SheepCountFollowsTheCommand) {
  WorldConfig c;
  c.sheep = 2;
  World world(c);
  world.set_sheep_count(5);
  world.step(0.01);
  EXPECT_EQ(world.sheep().size(), 5u);
  world.set_sheep_count(1);
  EXPECT_EQ(world.sheep().size(), 1u);
  EXPECT_THROW(world.set_sheep_count(-1), std::invalid_argument);
}

TEST(World, BadInputIsRefused) {
  WorldConfig c;
  c.speed_mm_s = std::nan("");
  EXPECT_THROW(World{c}, std::invalid_argument);
  c = WorldConfig{};
  c.sheep = 200;
  EXPECT_THROW(World{c}, std::invalid_argument);
  World world(empty_field());
  EXPECT_THROW(world.step(0.0), std::invalid_argument);
  EXPECT_THROW(world.step(std::nan("")), std::invalid_argument);
  EXPECT_THROW(world.add_sheep(-5, 100, 0, 30), std::invalid_argument);
  world.set_tool_tip(Eigen::Vector3d(std::nan(""), 0, 0));  // ignored, no crash
  world.step(0.01);
}

}  // namespace
}  // namespace ephor::sim
