#include "common/sphere/scan_line_extent.h"

#include <cmath>

#include <gtest/gtest.h>

#include "common/sphere/range_simulator.h"

namespace ephor::sphere {
namespace {

constexpr double kDeg = M_PI / 180.0;

// A hand-made noise-free line at a fixed elevation across a static sphere,
// pulses every `step_deg` in azimuth over [-1.5, 1.5] deg.
ScanLine line_at(int64_t id, double elevation_rad, double t_s, const Eigen::Vector3d& centre,
                 double step_deg = 0.0005) {
  ScanLine line{id, {}};
  const int n = static_cast<int>(std::lround(3.0 / step_deg));
  for (int k = 0; k <= n; ++k) {
    const double az = (-1.5 + k * step_deg) * kDeg;
    Pulse p;
    p.t_s = t_s + k * 1e-7;
    p.azimuth_rad = az;
    p.elevation_rad = elevation_rad;
    const auto r =
        ray_sphere_range(Eigen::Vector3d::Zero(), ray_direction(az, elevation_rad), centre, 0.08);
    p.range_m = r ? *r : std::nan("");
    line.pulses.push_back(p);
  }
  return line;
}

TEST(ScanLineExtentTest, OneNoiseFreeLineThroughTheCentreGivesTheCentre) {
  const Eigen::Vector3d centre(0.05, 0.0, 5.0);
  const double el = std::atan2(centre.y(), std::hypot(centre.x(), centre.z()));
  Window w;
  w.lines.push_back(line_at(0, el, 0.1, centre));
  for (const ScanLineExtentConfig& base :
       {ScanLineExtentConfig::paper(), ScanLineExtentConfig::improved()}) {
    ScanLineExtentConfig c = base;
    c.min_lines = 1;
    const Estimate e = ScanLineExtent(c).locate(w);
    ASSERT_TRUE(e.ok) << e.reason;
    EXPECT_NEAR(e.position_m.x(), centre.x(), 1e-4);
    // y = sqrt(u^2 - l^2) is ill conditioned at the equator: l short by 1e-5
    // (the 0.0005 deg pulse spacing at 5 m is 44 um) gives y of ~1-3 mm.
    EXPECT_NEAR(e.position_m.y(), centre.y(), 4e-3);
    EXPECT_NEAR(e.position_m.z(), centre.z(), 1e-3);
    EXPECT_EQ(e.lines, 1);
  }
}

TEST(ScanLineExtentTest, SignOfEquations28And29AboveAndBelowTheLongestLine) {
  const Eigen::Vector3d centre(0.0, 0.0, 5.0);
  Window w;
  // Nine lines from 0.8 deg above to 0.8 deg below the centre (angular radius 0.917 deg).
  for (int j = 0; j < 9; ++j) {
    const double el_deg = 0.8 - 0.2 * j;
    w.lines.push_back(line_at(j, el_deg * kDeg, 0.01 * j, centre));
  }
  for (const ScanLineExtentConfig& c :
       {ScanLineExtentConfig::paper(), ScanLineExtentConfig::improved()}) {
    const std::vector<LineExtent> lines = ScanLineExtent(c).line_extents(w);
    ASSERT_EQ(lines.size(), 9u);
    for (const LineExtent& e : lines) {
      const double el_deg = 0.8 - 0.2 * static_cast<double>(e.line_index);
      if (el_deg > 0.1) {
        EXPECT_EQ(e.sign, -1) << el_deg;  // line above the centre
      }
      if (el_deg < -0.1) {
        EXPECT_EQ(e.sign, +1) << el_deg;
      }
      // Away from the equator each line alone finds the centre's height.
      if (std::abs(el_deg) > 0.3) {
        EXPECT_NEAR(e.position_m.y(), 0.0, 1e-3) << el_deg;
      }
    }
    const Estimate est = ScanLineExtent(c).locate(w);
    ASSERT_TRUE(est.ok);
    EXPECT_NEAR(est.position_m.y(), 0.0, 2e-3);
    EXPECT_NEAR(est.position_m.z(), 5.0, 3e-3);
  }
}

TEST(ScanLineExtentTest, RegressionOfEquations38To40OnHandMadeData) {
  const LineFit f = regress({0, 1, 2, 3}, {1, 3, 5, 7});
  EXPECT_NEAR(f.slope, 2.0, 1e-12);
  EXPECT_NEAR(f.x0, 1.0, 1e-12);
  // Least squares through (0,0), (1,1), (2,1): slope 0.5, intercept 1/6.
  const LineFit g = regress({0, 1, 2}, {0, 1, 1});
  EXPECT_NEAR(g.slope, 0.5, 1e-12);
  EXPECT_NEAR(g.x0, 1.0 / 6.0, 1e-12);
  // Weighted: a zero-weight outlier is ignored.
  const std::vector<double> w = {1, 1, 1, 0};
  const LineFit h = regress({0, 1, 2, 3}, {1, 3, 5, 100}, &w);
  EXPECT_NEAR(h.slope, 2.0, 1e-12);
  EXPECT_NEAR(h.x0, 1.0, 1e-12);
}

TEST(ScanLineExtentTest, ThresholdsTheFarBackgroundAndSaysWhyWithNoSphere) {
  RangeSimulatorConfig c = RangeSimulator::paper_trial(10.0, 4);
  c.background.enabled = true;
  c.background.below_elevation_deg = 0.1;  // the wall behind the lower half
  RangeSimulator sim(c);
  Window w{0.0, 0.5, sim.scan(0.0, 0.5)};
  const Estimate e = ScanLineExtent(ScanLineExtentConfig::improved()).locate(w);
  ASSERT_TRUE(e.ok) << e.reason;
  const Eigen::Vector3d truth = c.sphere.centre_at(e.t_s);
  EXPECT_NEAR((e.position_m - truth).norm(), 0.0, 0.02);

  // No sphere: only the wall and misses.
  c.sphere.position_at_t0_m = Eigen::Vector3d(0, 0, -10);
  RangeSimulator empty(c);
  const Estimate none = ScanLineExtent().locate({0.0, 0.5, empty.scan(0.0, 0.5)});
  EXPECT_FALSE(none.ok);
  EXPECT_EQ(none.reason, "no returns closer than the background threshold");
}

TEST(ScanLineExtentTest, LinesCutByTheFrameEdgeAreRejectedWithAReason) {
  // The sphere straddles the frame's right edge: no line finds both edges.
  const Eigen::Vector3d centre(std::tan(1.5 * kDeg) * 5.0, 0.0, 5.0);
  Window w;
  for (int j = 0; j < 5; ++j)
    w.lines.push_back(line_at(j, (0.2 - 0.1 * j) * kDeg, 0.01 * j, centre));
  const Estimate e = ScanLineExtent().locate(w);
  EXPECT_FALSE(e.ok);
  EXPECT_NE(e.reason.find("5 cut by the frame or window edge"), std::string::npos) << e.reason;
}

TEST(ScanLineExtentTest, PaperTrialAtFiveMetresIsWithinTheRequirement) {
  RangeSimulator sim(RangeSimulator::paper_trial(5.0, 21));
  const Window w{0.0, 0.5, sim.scan(0.0, 0.5)};
  const Estimate e = ScanLineExtent(ScanLineExtentConfig::improved()).locate(w);
  ASSERT_TRUE(e.ok) << e.reason;
  const Eigen::Vector3d err = e.position_m - sim.config().sphere.centre_at(e.t_s);
  EXPECT_LT(err.cwiseAbs().maxCoeff(), 0.016);  // 2 sigma of the 8 mm requirement
  EXPECT_NEAR(e.velocity_m_s.x(), 0.051, 0.05);
}

}  // namespace
}  // namespace ephor::sphere
