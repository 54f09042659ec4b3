#include "common/sphere/guidance/sphere_tracker.h"

#include <cmath>
#include <cstdio>
#include <random>

#include <gtest/gtest.h>

namespace ephor::sphere {
namespace {

TEST(SphereTracker, PaperSigmaIsEightMillimetresOutToTwentyMetres) {
  EXPECT_DOUBLE_EQ(paper_measurement_sigma_m(1.0).x(), 0.008);
  EXPECT_DOUBLE_EQ(paper_measurement_sigma_m(20.0).z(), 0.008);
  EXPECT_DOUBLE_EQ(paper_measurement_sigma_m(40.0).y(), 0.016);
}

// A constant-velocity track at the locator's rate (2 Hz), 8 mm noise per
// axis: after 20 s the filter's position is well inside the measurement
// noise and its velocity within a few mm/s, and both errors sit inside the
// filter's own 3-sigma.
TEST(SphereTracker, ConvergesOnANoisyConstantVelocityTrack) {
  const Eigen::Vector3d p0(0.3, -0.2, 15.0), v(0.05, -0.03, -0.2);
  const double sigma = 0.008;
  double sum_sq = 0.0;
  int n = 0;
  for (uint64_t seed : {1u, 2u, 3u}) {
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> noise(0.0, sigma);
    SphereTracker f;
    for (int k = 0; k < 40; ++k) {
      const double t = 0.25 + 0.5 * k;
      const Eigen::Vector3d truth = p0 + v * t;
      const Eigen::Vector3d z = truth + Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
      const auto u = f.update(t, z, Eigen::Vector3d::Constant(sigma));
      EXPECT_TRUE(u == SphereTracker::Update::kAccepted ||
                  u == SphereTracker::Update::kInitialised);
      if (k < 20) continue;
      // Second half: the filter has converged.
      const TrackPrediction s = f.predict(t);
      const Eigen::Vector3d dp = s.position_m - truth, dv = s.velocity_m_s - v;
      sum_sq += dp.squaredNorm();
      n += 3;
      for (int i = 0; i < 3; ++i) {
        EXPECT_LT(std::abs(dp[i]), 3.5 * s.position_sigma_m[i]) << "seed " << seed << " k " << k;
        EXPECT_LT(std::abs(dv[i]), 3.5 * s.velocity_sigma_m_s[i]) << "seed " << seed << " k " << k;
        EXPECT_LT(std::abs(dv[i]), 0.003) << "seed " << seed << " k " << k;
        EXPECT_LT(s.position_sigma_m[i],
                  0.6 * sigma);  // steady state with the process noise
      }
    }
  }
  // About 8 mm * sqrt(4 / k) for a straight-line fit to k points: 2.5 mm at 40.
  const double rms = std::sqrt(sum_sq / n);
  std::printf("filtered position error, rms over the second half: %.2f mm\n", rms * 1e3);
  EXPECT_LT(rms, 0.5 * sigma);
}

// The chaser's burns are inputs: a track whose relative velocity jumps by
// the announced amount is followed without a lag.
TEST(SphereTracker, KnownVelocityChangesAreFollowedWithoutLag) {
  SphereTracker f;
  const Eigen::Vector3d dv(0.0, 0.0, -0.025);
  Eigen::Vector3d p(0.0, 0.0, 10.0), v(0.0, 0.0, -0.1);
  double t = 0.0;
  for (int k = 0; k < 20; ++k) {  // noise-free, to isolate the model
    const double t_next = 0.25 + 0.5 * k;
    p += v * (t_next - t);
    t = t_next;
    f.update(t, p, Eigen::Vector3d::Constant(0.008));
  }
  f.schedule_velocity_change(10.0, dv);  // burn at 10 s
  const TrackPrediction at11 = f.predict(11.0);
  p += v * (10.0 - t) + (v + dv) * 1.0;
  EXPECT_NEAR(at11.position_m.z(), p.z(), 1e-3);
  EXPECT_NEAR(at11.velocity_m_s.z(), -0.125, 1e-3);
  EXPECT_EQ(f.update(10.75, p - (v + dv) * 0.25, Eigen::Vector3d::Constant(0.008)),
            SphereTracker::Update::kAccepted);
  EXPECT_NEAR(f.predict(10.75).velocity_m_s.z(), -0.125, 1e-3);
}

// An estimate 5 cm out on a track good to a few mm (about 6 sigma): used,
// but pulls the track no further than one at the gate (4 sigma) would.
TEST(SphereTracker, DownweightsAnEstimateBeyondTheGate) {
  SphereTracker f, g;
  for (int k = 0; k < 10; ++k) {
    f.update(0.5 * k, Eigen::Vector3d(0, 0, 5.0), Eigen::Vector3d::Constant(0.008));
    g.update(0.5 * k, Eigen::Vector3d(0, 0, 5.0), Eigen::Vector3d::Constant(0.008));
  }
  const double sy = std::sqrt(
      f.predict(5.0).position_sigma_m.y() * f.predict(5.0).position_sigma_m.y() + 0.008 * 0.008);
  EXPECT_EQ(f.update(5.0, Eigen::Vector3d(0, 0.05, 5.0), Eigen::Vector3d::Constant(0.008)),
            SphereTracker::Update::kDownweighted);
  const double at_gate = std::sqrt(16.27) * sy;
  EXPECT_EQ(
      g.update(5.0, Eigen::Vector3d(0, at_gate * 0.999, 5.0), Eigen::Vector3d::Constant(0.008)),
      SphereTracker::Update::kAccepted);
  // About as far as the one at the gate (the inflated sigma also changes the
  // gain's split between position and velocity), much less than a full update.
  EXPECT_LT(f.predict(5.0).position_m.y(), g.predict(5.0).position_m.y());
  EXPECT_GT(f.predict(5.0).position_m.y(), 0.8 * g.predict(5.0).position_m.y());
}

TEST(SphereTracker, GatesOutliersAndStartsAgainOnANewSphere) {
  SphereTracker f;
  for (int k = 0; k < 10; ++k) {
    f.update(0.5 * k, Eigen::Vector3d(0, 0, 5.0), Eigen::Vector3d::Constant(0.008));
  }
  EXPECT_EQ(f.update(5.0, Eigen::Vector3d(0, 0, 6.0), Eigen::Vector3d::Constant(0.008)),
            SphereTracker::Update::kRejected);
  EXPECT_EQ(f.update(5.5, Eigen::Vector3d(0, 0, 20.0), Eigen::Vector3d::Constant(0.008)),
            SphereTracker::Update::kRejected);
  EXPECT_EQ(f.update(6.0, Eigen::Vector3d(0, 0, 20.0), Eigen::Vector3d::Constant(0.008)),
            SphereTracker::Update::kReinitialised);
  EXPECT_NEAR(f.predict(6.0).position_m.z(), 20.0, 1e-9);
  EXPECT_EQ(f.update(5.0, Eigen::Vector3d(0, 0, 20.0), Eigen::Vector3d::Constant(0.008)),
            SphereTracker::Update::kOutOfOrder);
}

}  // namespace
}  // namespace ephor::sphere
