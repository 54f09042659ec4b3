#include "common/sphere/range_simulator.h"

#include <cmath>

#include <gtest/gtest.h>

namespace ephor::sphere {
namespace {

TEST(RaySphereRangeTest, HandCheckedCases) {
  const Eigen::Vector3d o = Eigen::Vector3d::Zero();
  // Straight at a sphere 5 m away: the near surface at 5 - 0.08.
  EXPECT_NEAR(*ray_sphere_range(o, Eigen::Vector3d::UnitZ(), {0, 0, 5}, 0.08), 4.92, 1e-12);
  // Off-centre by 0.06 m sideways (perpendicular offset of the ray):
  // 5 - sqrt(0.08^2 - 0.06^2) = 5 - 0.052915 = 4.947085.
  EXPECT_NEAR(*ray_sphere_range(o, Eigen::Vector3d::UnitZ(), {0.06, 0, 5}, 0.08),
              5.0 - std::sqrt(0.0064 - 0.0036), 1e-12);
  // Misses by 1 mm, and a sphere behind the sensor.
  EXPECT_FALSE(ray_sphere_range(o, Eigen::Vector3d::UnitZ(), {0.081, 0, 5}, 0.08));
  EXPECT_FALSE(ray_sphere_range(o, Eigen::Vector3d::UnitZ(), {0, 0, -5}, 0.08));
  // A tilted ray: direction at azimuth a toward a centre on that ray at 2 m.
  const Eigen::Vector3d d = ray_direction(0.1, -0.05);
  EXPECT_NEAR(*ray_sphere_range(o, d, 2.0 * d, 0.08), 1.92, 1e-12);
  // Inside the sphere: the far wall.
  EXPECT_NEAR(*ray_sphere_range(o, Eigen::Vector3d::UnitZ(), {0, 0, 0.03}, 0.08), 0.11, 1e-12);
}

TEST(RangeSimulatorTest, FrameIsEquations35To37) {
  const Eigen::Vector3d p = to_cartesian(0.3, 0.2, 2.0);
  EXPECT_NEAR(p.x(), 2.0 * std::sin(0.3) * std::cos(0.2), 1e-15);
  EXPECT_NEAR(p.y(), 2.0 * std::sin(0.2), 1e-15);
  EXPECT_NEAR(p.z(), 2.0 * std::cos(0.3) * std::cos(0.2), 1e-15);
}

TEST(RangeSimulatorTest, NoiseFreeHitsLieOnTheMovingSphere) {
  RangeSimulatorConfig c = RangeSimulator::paper_trial(5.0, 3);
  c.noise = {0.0, 0.0};
  RangeSimulator sim(c);
  const std::vector<ScanLine> lines = sim.scan(0.0, 0.5);
  int pulses = 0, hits = 0;
  for (const ScanLine& line : lines) {
    for (const Pulse& p : line.pulses) {
      ++pulses;
      if (!p.has_range()) continue;
      ++hits;
      const Eigen::Vector3d q = to_cartesian(p.azimuth_rad, p.elevation_rad, p.range_m);
      EXPECT_NEAR((q - c.sphere.centre_at(p.t_s)).norm(), 0.08, 1e-9);
    }
  }
  EXPECT_EQ(pulses, 5000);  // 10 kHz for 0.5 s
  // The sphere (angular radius 0.917 deg) covers pi 0.917^2 / (2 x 1.116)^2
  // = 53 % of the frame: ~2650 of 5000 pulses.
  EXPECT_GT(hits, 2400);
  EXPECT_LT(hits, 2900);
  EXPECT_EQ(lines.size(), 224u);  // 0.5 s / (2 x 1.116 deg / 1000 deg/s)
}

TEST(RangeSimulatorTest, NoiseHasTheConfiguredSigmaAndIsSeeded) {
  RangeSimulatorConfig c = RangeSimulator::paper_trial(20.0, 11);
  c.background.enabled = true;
  c.background.below_elevation_deg = 0.0;
  RangeSimulator a(c), b(c);
  const auto la = a.scan(0.0, 0.5);
  const auto lb = b.scan(0.0, 0.5);
  ASSERT_EQ(la.size(), lb.size());
  EXPECT_EQ(la[7].pulses[3].azimuth_rad, lb[7].pulses[3].azimuth_rad);
  EXPECT_NE(la[7].pulses[3].azimuth_rad, la[7].pulses[4].azimuth_rad);
  double sum = 0.0, sum2 = 0.0;
  int n = 0;
  for (const ScanLine& line : la) {
    for (const Pulse& p : line.pulses) {
      if (p.has_range() && p.range_m > 50.0) {  // the wall: true range 60 m
        sum += p.range_m - 60.0;
        sum2 += (p.range_m - 60.0) * (p.range_m - 60.0);
        ++n;
      }
    }
  }
  ASSERT_GT(n, 1000);
  EXPECT_NEAR(sum / n, 0.0, 0.003);
  EXPECT_NEAR(std::sqrt(sum2 / n), 0.02, 0.002);
}

// Found by the fuzz target sphere_ranger (--window-s 0.1): the window
// starting at 3 * 0.1 = 0.30000000000000004 s had its first pulse at 0.3 s,
// a rounding error before it, scanned as line -1: the ranger published the
// previous window's last line id again.
TEST(RangeSimulatorTest, AWindowStartingARoundingErrorLateStartsAtItsFirstLine) {
  RangeSimulatorConfig c;
  c.scanner.half_extent_deg = 2.0;
  c.sphere = SphereTrajectory::paper_trial(10.0, 0.35);
  c.noise.range_sigma_m = 0.0;
  c.noise.angle_sigma_rad = 0.0;
  RangeSimulator sim(c);
  const double t0 = 3 * 0.1;
  ASSERT_GT(t0, 0.3);  // the rounding this is about
  const std::vector<ScanLine> lines = sim.scan(t0, 0.1, 100);
  ASSERT_FALSE(lines.empty());
  EXPECT_EQ(lines.front().id, 100);
  for (size_t i = 1; i < lines.size(); ++i) EXPECT_GT(lines[i].id, lines[i - 1].id);
  // The first pulse is the raster's upper left.
  const Pulse& p = lines.front().pulses.front();
  EXPECT_NEAR(p.azimuth_rad, -2.0 * M_PI / 180.0, 1e-9);
  EXPECT_NEAR(p.elevation_rad, 2.0 * M_PI / 180.0, 1e-9);
}

}  // namespace
}  // namespace ephor::sphere
