// The whole sphere system (deploy/sphere.pbtxt) started headless by the
// launcher, as a user runs it, in a private network namespace: the ranger
// (the sphere 5 m out, to keep the run short), the locator (Scan Line
// Extent, improved) and the guidance closing the loop through the ranger's
// chaser. A listener on the same bus checks what a user cares about:
// estimates every half second, each within the 4 mm sigma target of the ranger's ground
// truth at the estimate's time, a command for each, and the run ending by
// itself with the sphere captured (below 2 cm/s, within 2 cm of the axis),
// even with malformed messages thrown at each process along the way.

#include <algorithm>
#include <cmath>
#include <mutex>
#include <vector>

#include <gtest/gtest.h>

#include "common/lcm/bus.h"
#include "common/sphere/sphere_channels.h"
#include "ephor/sphere_estimate_t.hpp"
#include "ephor/sphere_guidance_t.hpp"
#include "ephor/sphere_scan_line_t.hpp"
#include "ephor/sphere_truth_t.hpp"
#include "tests/integration/harness.h"

namespace ephor::testing {
namespace {

using std::chrono::seconds;

constexpr const char* kUrl = "udpm://239.255.76.67:7670?ttl=0&recv_buf_size=16777216";

struct Heard {
  std::mutex mutex;
  std::vector<sphere_estimate_t> estimates;
  std::vector<sphere_truth_t> truth;
  std::vector<sphere_guidance_t> guidance;
};

// The truth sample of the same approach nearest to t_s, moved to t_s along
// its velocity (exact within the ranger's window: the motion is linear there).
bool truth_at(const std::vector<sphere_truth_t>& truth, double t_s, double out[3]) {
  const sphere_truth_t* best = nullptr;
  for (const auto& s : truth) {
    if (s.phase != sphere_truth_t::PHASE_APPROACH) continue;
    if (!best || std::abs(s.t_s - t_s) < std::abs(best->t_s - t_s)) best = &s;
  }
  if (!best || std::abs(best->t_s - t_s) > 0.1) return false;
  // Only within the ranger's window (velocity changes at 0.5 s boundaries).
  if (std::floor(best->t_s / 0.5) != std::floor(t_s / 0.5)) return false;
  for (int i = 0; i < 3; ++i)
    out[i] = best->position_m[i] + best->velocity_m_s[i] * (t_s - best->t_s);
  return true;
}

TEST(Sphere, ApproachFromFiveMetresIsLocatedAtTwoHertzAndCaptured) {
  Heard heard;
  Bus bus(kUrl, "sphere-test");
  bus.subscribe<sphere_estimate_t>(sphere::channels::kEstimate, [&](const sphere_estimate_t& m) {
    if (m.header.sender == "sphere-test") return;  // our own bad input
    std::lock_guard<std::mutex> lock(heard.mutex);
    heard.estimates.push_back(m);
  });
  bus.subscribe<sphere_truth_t>(sphere::channels::kTruth, [&](const sphere_truth_t& m) {
    std::lock_guard<std::mutex> lock(heard.mutex);
    heard.truth.push_back(m);
  });
  bus.subscribe<sphere_guidance_t>(sphere::channels::kGuidance, [&](const sphere_guidance_t& m) {
    if (m.header.sender == "sphere-test") return;  // our own bad input
    std::lock_guard<std::mutex> lock(heard.mutex);
    heard.guidance.push_back(m);
  });
  bus.start();

  Processes p;
  p.start("launch", bin("ephor-launch"),
          {source_path("deploy/sphere.pbtxt"), "--headless", "--duration", "75", "--start_m", "5",
           "--seed", "2", "--max_s", "70"},
          {{"LCM_DEFAULT_URL", kUrl}});
  // Bad input while the loop runs: a scan line with a NaN time, bytes that
  // are no message at all, an estimate with a NaN position, a command with
  // a NaN velocity. Each is refused and counted; the approach goes on.
  ASSERT_TRUE(wait_until(
      [&] {
        std::lock_guard<std::mutex> lock(heard.mutex);
        return heard.estimates.size() >= 4;
      },
      seconds(30)))
      << "no estimates";
  {
    sphere_scan_line_t line{};
    line.line = 1;
    line.window_s = 0.5;
    line.num_pulses = 2;
    line.t_s = {std::nan(""), 1.0};
    line.azimuth_rad = {0.0, 0.0};
    line.elevation_rad = {0.0, 0.0};
    line.range_m = {5.0, 5.0};
    bus.publish(sphere::channels::kScanLine, line);
    const char garbage[] = "not an lcm message";
    bus.publish_raw(sphere::channels::kScanLine, garbage, sizeof garbage);
    sphere_estimate_t est{};
    est.window = 1000000;
    est.window_end_s = 500000.5;
    est.ok = true;
    est.t_s = 500000.25;
    est.position_m[0] = std::nan("");
    bus.publish(sphere::channels::kEstimate, est);
    sphere_guidance_t cmd{};
    cmd.apply_t_s = 0.0;
    cmd.chaser_velocity_m_s[2] = std::nan("");
    bus.publish(sphere::channels::kGuidance, cmd);
  }
  ASSERT_TRUE(wait_until(
      [&] {
        for (const auto& e : p.exits())
          if (e.name == "launch") return true;
        return false;
      },
      seconds(90)))
      << "the run did not end";
  EXPECT_TRUE(p.has_line("launch", "SPHERE_SCAN_LINE from sphere-test refused"));
  EXPECT_TRUE(p.has_line("launch", "SPHERE_ESTIMATE window 1000000 from sphere-test ignored"));
  EXPECT_TRUE(p.has_line("launch", "SPHERE_GUIDANCE from sphere-test ignored"));
  ASSERT_EQ(p.exits().front().code, 0) << "the launcher reported a failed process";
  // The verdict is published just before the ranger exits; give the bus a moment to deliver it.
  wait_until(
      [&] {
        std::lock_guard<std::mutex> lock(heard.mutex);
        return std::any_of(heard.truth.begin(), heard.truth.end(), [](const sphere_truth_t& t) {
          return t.phase != sphere_truth_t::PHASE_APPROACH;
        });
      },
      std::chrono::milliseconds(2000));
  bus.stop();

  std::lock_guard<std::mutex> lock(heard.mutex);
  // The verdict.
  const sphere_truth_t* verdict = nullptr;
  for (const auto& t : heard.truth)
    if (t.phase != sphere_truth_t::PHASE_APPROACH) verdict = &t;
  ASSERT_NE(verdict, nullptr) << "no verdict on SPHERE_TRUTH";
  std::fprintf(stderr, "verdict: %s\n", verdict->verdict.c_str());
  EXPECT_EQ(static_cast<int>(verdict->phase), static_cast<int>(sphere_truth_t::PHASE_CAPTURED))
      << verdict->verdict;
  EXPECT_LT(verdict->capture_speed_m_s, 0.02);
  EXPECT_LT(verdict->capture_offset_m, 0.02);
  EXPECT_LT(verdict->capture_t_s, 60.0) << "the approach took too long";

  // Estimates at 2 Hz: one per window, consecutive windows, half a second apart.
  const auto& est = heard.estimates;
  ASSERT_GE(est.size(), 20u);
  int gaps = 0;
  for (size_t i = 1; i < est.size(); ++i) gaps += est[i].window != est[i - 1].window + 1 ? 1 : 0;
  EXPECT_LE(gaps, 1) << "windows without an estimate";
  const double span_s = static_cast<double>(est.back().utime - est.front().utime) * 1e-6;
  const double rate_hz = static_cast<double>(est.size() - 1) / span_s;
  std::fprintf(stderr, "%zu estimates at %.3f Hz\n", est.size(), rate_hz);
  EXPECT_NEAR(rate_hz, 2.0, 0.1);

  // Each within the sigma target of the truth at its time.
  int ok = 0, compared = 0;
  double sum_sq[3] = {0, 0, 0}, worst = 0.0;
  for (const auto& e : est) {
    if (!e.ok) continue;
    ++ok;
    double t[3];
    if (!truth_at(heard.truth, e.t_s, t)) continue;
    ++compared;
    for (int i = 0; i < 3; ++i) {
      const double d = e.position_m[i] - t[i];
      sum_sq[i] += d * d;
      worst = std::max(worst, std::abs(d));
    }
  }
  EXPECT_GE(ok, static_cast<int>(est.size()) - 2) << "windows with no estimate";
  ASSERT_GE(compared, ok / 2) << "too few estimates had a truth sample in their window";
  std::fprintf(
      stderr, "%d estimates against the truth: rms x %.1f y %.1f z %.1f mm, worst %.1f mm\n",
      compared, std::sqrt(sum_sq[0] / compared) * 1e3, std::sqrt(sum_sq[1] / compared) * 1e3,
      std::sqrt(sum_sq[2] / compared) * 1e3, worst * 1e3);
  // The sigma target for Scan Line Extent (4 mm per axis; a run
  // gives about 0.3-0.8 mm rms from 5 m in).
  for (int i = 0; i < 3; ++i) EXPECT_LT(std::sqrt(sum_sq[i] / compared), 0.004) << "axis " << i;
  EXPECT_LT(worst, 0.015);

  // Guidance answered each estimate.
  EXPECT_GE(heard.guidance.size() + 2, est.size());
}

}  // namespace
}  // namespace ephor::testing
