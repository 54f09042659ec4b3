#include "common/sphere/sphere_fitter.h"

#include <cmath>

#include <gtest/gtest.h>

#include "common/sphere/range_simulator.h"

namespace ephor::sphere {
namespace {

std::vector<TimedPoint> noise_free_points(const SphereTrajectory& s, double distance) {
  RangeSimulatorConfig c = RangeSimulator::paper_trial(distance, 1);
  c.sphere = s;
  c.noise = {0.0, 0.0};
  RangeSimulator sim(c);
  std::vector<TimedPoint> pts;
  for (const ScanLine& line : sim.scan(0.0, 0.5)) {
    for (const Pulse& p : line.pulses) {
      if (p.has_range())
        pts.push_back({to_cartesian(p.azimuth_rad, p.elevation_rad, p.range_m), p.t_s});
    }
  }
  return pts;
}

TEST(SphereFitterTest, NoiseFreePointsRecoverCentreAndVelocity) {
  for (double d : {2.0, 10.0}) {
    const SphereTrajectory s = SphereTrajectory::paper_trial(d);
    const std::vector<TimedPoint> pts = noise_free_points(s, d);
    ASSERT_GT(pts.size(), 50u);
    for (const SphereFitterConfig& c :
         {SphereFitterConfig::paper(), SphereFitterConfig::improved()}) {
      SphereFitterConfig cc = c;
      cc.range_sigma_m = 1e-3;  // weights only; no noise-bias term worth speaking of
      cc.angle_sigma_rad = 1e-5;
      const SphereFit f = SphereFitter(cc).fit(pts);
      ASSERT_TRUE(f.converged) << d;
      const Eigen::Vector3d truth = s.centre_at(f.t_ref_s);
      EXPECT_NEAR((f.centre_m - truth).norm(), 0.0, 2e-4) << d << " m";
      EXPECT_NEAR((f.velocity_m_s - s.velocity_m_s).norm(), 0.0, 3e-3) << d << " m";
    }
  }
}

TEST(SphereFitterTest, NoSphereGivesAReasonNotACrash) {
  Window w{0.0, 0.5, {{0, {{0.0, 0.0, 0.0, std::nan("")}, {0.1, 0.01, 0.0, 70.0}}}}};
  const Estimate e = SphereFitter().locate(w);
  EXPECT_FALSE(e.ok);
  EXPECT_EQ(e.reason, "no returns closer than the background threshold");
  Window few{0.0, 0.5, {{0, {{0.0, 0.0, 0.0, 5.0}, {0.1, 0.001, 0.0, 5.0}}}}};
  EXPECT_EQ(SphereFitter().locate(few).reason, "only 2 points on the sphere (need 12)");
}

}  // namespace
}  // namespace ephor::sphere
