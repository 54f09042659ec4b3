#include "common/sphere/world/ranger_world.h"

#include <gtest/gtest.h>

#include "common/sphere/sphere_locator.h"

namespace ephor::sphere {
namespace {

RangerWorldConfig at(double z, Eigen::Vector3d drift = Eigen::Vector3d::Zero()) {
  RangerWorldConfig c;
  c.motion.start_position_m = {0.0, 0.0, z};
  c.motion.target_velocity_m_s = drift;
  c.seed = 3;
  return c;
}

TEST(RangerWorld, LinesComeOutInOrderOncePerWindowWithTheirMarks) {
  RangerWorld w(at(5.0, RelativeMotionConfig::table1_drift(5.0)));
  std::vector<RangerLine> all;
  int64_t next_id = 0;
  for (int step = 1; step <= 100; ++step) {  // 1 s in 10 ms steps
    const double t = 0.01 * step;
    for (RangerLine& l : w.advance_to(t)) {
      EXPECT_LE(l.ready_t_s, t + 1e-12);
      EXPECT_EQ(l.line.id, next_id++) << "line ids run on across windows without gaps";
      all.push_back(std::move(l));
    }
  }
  ASSERT_FALSE(all.empty());
  int marks = 0;
  for (const RangerLine& l : all) {
    for (const Pulse& p : l.line.pulses) {
      EXPECT_GE(p.t_s, 0.5 * static_cast<double>(l.window) - 1e-12);
      EXPECT_LT(p.t_s, 0.5 * static_cast<double>(l.window + 1));
    }
    if (l.last_in_window) ++marks;
  }
  EXPECT_EQ(marks, 2) << "windows 0 and 1 are complete by t = 1 s";
  // Table 2's 5 m frame is 1.12 deg for a sphere through the boresight at
  // mid-window; ours starts on it and drifts 2.55 cm up and right by the
  // window's end: 1.05 * (atan(0.0255 / 4.982) + asin(0.08 / 4.982)) = 1.274 deg.
  const double end_deg = (std::atan(0.0255 / 4.982) + std::asin(0.08 / 4.982)) * 180.0 / M_PI;
  EXPECT_NEAR(all.front().half_extent_deg, 1.05 * end_deg, 0.002);
}

TEST(RangerWorld, ACommandTakesEffectAtTheFirstWindowStartAtOrAfterItsTime) {
  RangerWorld w(at(10.0));
  w.advance_to(0.1);
  EXPECT_TRUE(w.command(1.0, Eigen::Vector3d(0, 0, 0.02)));
  w.advance_to(0.9);
  EXPECT_EQ(w.motion().chaser_velocity().z(), 0.0) << "not before 1.0 s";
  w.advance_to(1.0);
  EXPECT_NEAR(w.motion().chaser_velocity().z(), 0.02, 1e-12);
  EXPECT_NEAR(w.truth_at(1.0).velocity_m_s.z(), -0.02, 1e-12);
  EXPECT_FALSE(w.command(2.0, Eigen::Vector3d(std::nan(""), 0, 0)));
}

TEST(RangerWorld, JudgesTheCaptureAndEndsTheApproach) {
  // 1.2 m, closing at 1 cm/s, centred: reaches 1 m at 20 s and is captured.
  RangerWorld w(at(1.2, Eigen::Vector3d(0, 0, -0.01)));
  double t = 0.0;
  while (!w.finished() && t < 30.0) {
    t += 0.05;
    w.advance_to(t);
  }
  ASSERT_TRUE(w.finished());
  ASSERT_EQ(w.verdicts().size(), 1u);
  EXPECT_TRUE(w.verdicts()[0].captured) << w.verdicts()[0].text;
  EXPECT_NEAR(w.verdicts()[0].t_s, 20.0, 1e-6);
}

TEST(RangerWorld, GivesUpAfterMaxSeconds) {
  RangerWorldConfig c = at(5.0);
  c.max_s = 3.0;
  RangerWorld w(c);
  w.advance_to(3.2);
  ASSERT_TRUE(w.finished());
  EXPECT_FALSE(w.verdicts()[0].captured);
  EXPECT_NEAR(w.verdicts()[0].t_s, 3.0, 1e-9);
}

TEST(RangerWorld, AFreshSphereForEachApproach) {
  // From 1.1 m at 4.8 cm/s: at 1 m after 2.083 s (too fast); the next
  // window (from 2.5 s) has a fresh sphere at the start distance.
  RangerWorldConfig c = at(1.1, Eigen::Vector3d(0, 0, -0.048));
  c.approaches = 2;
  RangerWorld w(c);
  w.advance_to(2.1);
  ASSERT_EQ(w.verdicts().size(), 1u);
  EXPECT_FALSE(w.verdicts()[0].captured);
  EXPECT_NEAR(w.verdicts()[0].t_s, 0.1 / 0.048, 1e-9);
  EXPECT_FALSE(w.finished());
  EXPECT_EQ(w.approach(), 0);
  w.advance_to(2.5);
  EXPECT_EQ(w.approach(), 1);
  EXPECT_NEAR(w.truth_at(2.5).position_m.z(), 1.1, 1e-12);
}

TEST(RangerWorld, ItsWindowsLocateTheSphereWithinAFewMillimetres) {
  RangerWorld w(at(5.0, RelativeMotionConfig::table1_drift(5.0)));
  Window win;
  win.t_begin_s = 0.0;
  win.t_end_s = 0.5;
  for (RangerLine& l : w.advance_to(0.5)) {
    if (l.window == 0) win.lines.push_back(std::move(l.line));
  }
  const Estimate e = SphereLocator(LocatorConfig{}).locate(win);
  ASSERT_TRUE(e.ok) << e.reason;
  const Eigen::Vector3d truth = w.truth_at(e.t_s).position_m;
  EXPECT_LT((e.position_m - truth).cwiseAbs().maxCoeff(), 0.02)
      << "estimate " << e.position_m.transpose() << " truth " << truth.transpose();
}

TEST(RangerWorld, RefusesAStartInsideTheCaptureDistance) {
  EXPECT_THROW(RangerWorld{at(0.9)}, std::invalid_argument);
}

}  // namespace
}  // namespace ephor::sphere
