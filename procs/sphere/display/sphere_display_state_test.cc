#include "procs/sphere/display/sphere_display_state.h"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "common/fuzz/json_checks.h"

namespace ephor::sphere_display {
namespace {

constexpr double kDeg = 180.0 / 3.14159265358979323846;

// A line of `ranges` along azimuth 0, 0.01, 0.02 ... rad at elevation 0.005 rad.
ScanLineView line_of(int64_t line, int64_t window, bool last, std::vector<double> ranges) {
  ScanLineView l;
  l.line = line;
  l.window = window;
  l.last_in_window = last;
  l.half_extent_deg = 1.5;
  for (size_t i = 0; i < ranges.size(); ++i) {
    l.azimuth_rad.push_back(0.01 * static_cast<double>(i));
    l.elevation_rad.push_back(0.005);
  }
  l.range_m = std::move(ranges);
  return l;
}

TEST(SphereDisplayStateTest, ScanLineGivesOnePointPerReturnInItsRangeBin) {
  SphereDisplayState s;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  // Eight sphere returns 10.0 .. 10.7 m, one pulse with no return, one far background return.
  s.on_scan_line(line_of(1, 3, true, {10.0, 10.1, 10.2, 10.3, 10.4, 10.5, 10.6, 10.7, nan, 60.0}),
                 1'000'000);
  const auto scan = s.scan_json();
  ASSERT_FALSE(scan.is_null());
  EXPECT_EQ(scan["window"], 3);
  // The 2nd and 98th percentiles of eight ranges are the nearest and the farthest.
  EXPECT_NEAR(scan["range_lo_m"].get<double>(), 10.0, 1e-9);
  EXPECT_NEAR(scan["range_hi_m"].get<double>(), 10.7, 1e-9);
  const auto& pts = scan["points"];
  ASSERT_EQ(pts.size(), 9u);  // no point for the pulse without a return
  // Eight equal bins of 0.0875 m from 10.0 m: one return in each, nearest first.
  for (int i = 0; i < 8; ++i) {
    EXPECT_EQ(pts[i][3], i) << "range " << pts[i][2];
    EXPECT_NEAR(pts[i][0].get<double>(), 0.01 * i * kDeg, 1e-3);  // azimuth, deg
    EXPECT_NEAR(pts[i][1].get<double>(), 0.005 * kDeg, 1e-3);     // elevation, deg
  }
  EXPECT_EQ(pts[8][3], -1);  // the background
  const auto j = s.to_json(1'100'000);
  EXPECT_EQ(j["scan"]["points"], 9);
  EXPECT_EQ(j["scan"]["no_return"], 1);
  EXPECT_EQ(j["scan"]["background"], 1);
  EXPECT_EQ(j["scan"]["lines"], 1);
  EXPECT_NEAR(j["scan"]["age_ms"].get<double>(), 100.0, 1e-9);
}

TEST(SphereDisplayStateTest, AWindowIsShownOnceCompleteOrOvertaken) {
  SphereDisplayState s;
  s.on_scan_line(line_of(1, 5, false, {5.0, 5.1}), 1);
  EXPECT_EQ(s.scan_window(), -1);  // window 5 still being scanned
  EXPECT_TRUE(s.to_json(2)["scan"].is_null());
  s.on_scan_line(line_of(2, 5, false, {5.2}), 2);
  // Its last line was lost: the first line of window 6 completes it.
  s.on_scan_line(line_of(3, 6, false, {5.3}), 3);
  EXPECT_EQ(s.scan_window(), 5);
  EXPECT_EQ(s.to_json(4)["scan"]["lines"], 2);
  EXPECT_EQ(s.scan_json()["points"].size(), 3u);
  s.on_scan_line(line_of(4, 6, true, {5.4}), 5);
  EXPECT_EQ(s.scan_window(), 6);
  EXPECT_EQ(s.scan_json()["points"].size(), 2u);
}

TEST(SphereDisplayStateTest, EstimateAndFilteredSphereWithItsSigma) {
  SphereDisplayState s;
  EstimateView e;
  e.window = 7;
  e.ok = true;
  e.t_s = 3.75;
  e.position_m = {0.3, 0.4, 12.0};
  e.algorithm = "sle";
  s.on_estimate(e, 10);
  GuidanceView g;
  g.t_s = 3.75;
  g.position_m = {0.0, 0.0, 10.0};
  g.position_sigma_m = {0.01, 0.02, 0.03};
  g.phase = 1;
  g.estimates_used = 4;
  g.range_to_capture_m = 9.0;
  s.on_guidance(g, 10);
  const auto j = s.to_json(20);

  const auto& je = j["estimate"];
  EXPECT_TRUE(je["ok"].get<bool>());
  EXPECT_NEAR(je["range_m"].get<double>(), std::sqrt(0.09 + 0.16 + 144.0), 1e-4);
  EXPECT_NEAR(je["lateral_m"].get<double>(), 0.5, 1e-9);
  EXPECT_NEAR(je["azimuth_deg"].get<double>(), std::atan2(0.3, 12.0) * kDeg, 1e-4);
  EXPECT_NEAR(je["elevation_deg"].get<double>(), std::atan2(0.4, std::hypot(0.3, 12.0)) * kDeg,
              1e-4);

  const auto& jg = j["guidance"];
  EXPECT_EQ(jg["phase"], "closing");
  EXPECT_NEAR(jg["sigma_m"][0].get<double>(), 0.01, 1e-9);
  EXPECT_NEAR(jg["sigma_m"][2].get<double>(), 0.03, 1e-9);
  // 1 sigma across the line of sight at 10 m: 1 mrad and 2 mrad.
  EXPECT_NEAR(jg["sigma_deg"][0].get<double>(), 0.001 * kDeg, 1e-5);
  EXPECT_NEAR(jg["sigma_deg"][1].get<double>(), 0.002 * kDeg, 1e-5);
  // The 8 cm sphere at 10 m is asin(0.008) across its radius.
  EXPECT_NEAR(jg["radius_deg"].get<double>(), std::asin(0.008) * kDeg, 1e-4);
  EXPECT_NEAR(jg["range_to_capture_m"].get<double>(), 9.0, 1e-9);
  ASSERT_EQ(j["history"]["estimate"].size(), 1u);
  EXPECT_NEAR(j["history"]["guidance"][0][1].get<double>(), 10.0, 1e-9);
}

TEST(SphereDisplayStateTest, NoEstimateSaysWhyAndBadNumbersDrawNothing) {
  SphereDisplayState s;
  EstimateView e;
  e.ok = false;
  e.reason = "too few foreground points";
  s.on_estimate(e, 1);
  GuidanceView g;
  g.position_m = {std::nan(""), 0.0, 5.0};
  s.on_guidance(g, 1);
  const auto j = s.to_json(2);
  EXPECT_EQ(j["estimate"]["reason"], "too few foreground points");
  EXPECT_FALSE(j["estimate"].contains("position_m"));
  EXPECT_EQ(j["estimate"]["failed"], 1);
  EXPECT_TRUE(j["guidance"].is_null());
  EXPECT_TRUE(j["history"]["estimate"].empty());
  EXPECT_NO_THROW((void)j.dump());  // no NaN reaches the JSON
}

TEST(SphereDisplayStateTest, ApproachHistoryVerdictsAndAFreshSphere) {
  SphereDisplayState s;
  TruthView t;
  t.approach = 0;
  // One second of truth at 20 Hz closing at 1 m/s: kept every 0.25 s.
  for (int i = 0; i <= 20; ++i) {
    t.t_s = 0.05 * i;
    t.position_m = {0.02, 0.0, 3.0 - t.t_s};
    s.on_truth(t, i);
  }
  auto j = s.to_json(100);
  ASSERT_EQ(j["history"]["truth"].size(), 5u);  // 0, 0.25, 0.5, 0.75, 1.0 s
  EXPECT_NEAR(j["history"]["truth"][4][1].get<double>(), std::hypot(0.02, 2.0), 1e-4);
  EXPECT_NEAR(j["history"]["truth"][4][2].get<double>(), 0.02, 1e-9);
  EXPECT_EQ(j["truth"]["phase"], "approach");

  t.phase = 1;  // captured, published once more with the verdict
  t.verdict = "captured";
  t.capture_speed_m_s = 0.01;
  s.on_truth(t, 101);
  s.on_truth(t, 102);  // the same verdict again is not a second capture
  t.phase = 0;         // the next approach: a fresh sphere far away
  t.approach = 1;
  t.verdict = "";
  t.t_s = 1.1;
  t.position_m = {0.0, 0.0, 20.0};
  s.on_truth(t, 103);
  j = s.to_json(104);
  EXPECT_EQ(j["approaches"]["captured"], 1);
  EXPECT_EQ(j["approaches"]["missed"], 0);
  EXPECT_EQ(j["last_verdict"]["verdict"], "captured");
  EXPECT_EQ(j["last_verdict"]["approach"], 0);
  EXPECT_EQ(j["truth"]["approach"], 1);
  ASSERT_EQ(j["history"]["truth"].size(), 1u);  // the old approach's samples are gone
}

// What the fuzz target sphere_display found (issue 18): a pulse's angle or
// range above ~1e300 was written as null in /api/scan (rounded() to 3 or 4
// decimals overflowed to infinity). Such a number is kept as it is.
TEST(SphereDisplayStateTest, HugeNumbersStayFiniteInScanAndState) {
  SphereDisplayState s;
  ScanLineView l;
  l.window = 0;
  l.last_in_window = true;
  l.azimuth_rad = {0.0, 1e306};
  l.elevation_rad = {1e306, 0.0};
  l.range_m = {1e300, 10.0};
  s.on_scan_line(l, 1);
  TruthView t;
  t.position_m = {1e305, 0.0, 1.0};
  t.capture_offset_m = 1.7e308;
  t.phase = 2;
  s.on_truth(t, 2);
  const auto scan = s.scan_json();
  const auto state = s.to_json(3);
  EXPECT_EQ(fuzz::first_non_finite(scan), "") << scan.dump();
  EXPECT_EQ(fuzz::first_non_finite(state), "") << state.dump();
  ASSERT_EQ(scan["points"].size(), 2u);
  EXPECT_EQ(scan["points"][0][2].get<double>(), 1e300);
  EXPECT_EQ(state["last_verdict"]["capture_offset_m"].get<double>(), 1.7e308);
}

}  // namespace
}  // namespace ephor::sphere_display
