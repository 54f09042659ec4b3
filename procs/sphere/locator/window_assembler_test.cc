#include "procs/sphere/locator/window_assembler.h"

#include <cmath>
#include <cstdint>
#include <string>

#include <gtest/gtest.h>

namespace ephor::sphere {
namespace {

// A line of n pulses from t0 every 0.1 ms (10 kHz), all hitting at 5 m.
LineMessage line(int64_t id, double t0, int n, int64_t window = 0, bool last = false) {
  LineMessage m;
  m.line = id;
  m.window = window;
  m.window_s = 0.5;
  m.last_in_window = last;
  m.num_pulses = n;
  for (int i = 0; i < n; ++i) {
    m.t_s.push_back(t0 + 1e-4 * i);
    m.azimuth_rad.push_back(0.001 * i);
    m.elevation_rad.push_back(0.0);
    m.range_m.push_back(5.0);
  }
  return m;
}

TEST(WindowAssembler, RangerMarkCompletesTheWindow) {
  WindowAssembler a(0.5);
  EXPECT_EQ(a.add(line(0, 0.0, 10)), "");
  EXPECT_EQ(a.add(line(1, 0.001, 10)), "");
  EXPECT_TRUE(a.take_complete().empty()) << "no line of a later window, no mark yet";
  // The window's last line ends one pulse before 0.5 s.
  EXPECT_EQ(a.add(line(2, 0.5 - 1e-4 * 10, 10, 0, true)), "");
  const auto done = a.take_complete();
  ASSERT_EQ(done.size(), 1u);
  EXPECT_EQ(done[0].index, 0);
  EXPECT_EQ(done[0].lines_received, 3);
  EXPECT_EQ(done[0].lines_missing, 0);
  EXPECT_DOUBLE_EQ(done[0].window.t_begin_s, 0.0);
  EXPECT_DOUBLE_EQ(done[0].window.t_end_s, 0.5);
}

TEST(WindowAssembler, ALaterLineCompletesTheWindowWhenTheMarkIsLost) {
  WindowAssembler a(0.5);
  a.add(line(0, 0.0, 10));
  a.add(line(3, 0.2, 10));  // lines 1 and 2 lost
  a.add(line(10, 0.6, 10, 1));
  const auto done = a.take_complete();
  ASSERT_EQ(done.size(), 1u);
  EXPECT_EQ(done[0].lines_missing, 2);
  // A line for window 0 now is late.
  EXPECT_NE(a.add(line(4, 0.3, 5)).find("late"), std::string::npos);
  EXPECT_EQ(a.late(), 1);
}

TEST(WindowAssembler, ARestartedRangerIsFollowedNotRefusedAsLate) {
  WindowAssembler a(0.5);
  // Ten windows of one line each (window k's line at 0.5 k s), all located.
  for (int k = 0; k < 10; ++k) a.add(line(100 + k, 0.5 * k, 10, k));
  a.add(line(200, 5.0, 10, 10));
  ASSERT_EQ(a.take_complete().size(), 10u);
  // A line two windows back with an older counter is still late...
  EXPECT_NE(a.add(line(105, 4.0, 10, 8)).find("late"), std::string::npos);
  EXPECT_EQ(a.restarts(), 0);
  // ...but the scan clock and the counter back at the start: a new ranger.
  EXPECT_EQ(a.add(line(0, 0.0, 10, 0)), "");
  EXPECT_EQ(a.restarts(), 1);
  EXPECT_EQ(a.add(line(1, 0.6, 10, 1)), "");
  const auto done = a.take_complete();
  ASSERT_EQ(done.size(), 1u);
  EXPECT_EQ(done[0].index, 0);
  EXPECT_EQ(done[0].lines_received, 1) << "the old ranger's open window was dropped";
}

TEST(WindowAssembler, SplitsALineThatStraddlesItsWindowBoundary) {
  WindowAssembler a(0.25);     // the ranger's windows are 0.5 s
  a.add(line(0, 0.2495, 10));  // 0.2495 .. 0.2504
  a.add(line(1, 0.5, 10));
  const auto done = a.take_complete();
  ASSERT_EQ(done.size(), 2u);
  EXPECT_EQ(done[0].window.lines[0].pulses.size(), 5u);
  EXPECT_EQ(done[1].window.lines[0].pulses.size(), 5u);
}

TEST(WindowAssembler, RefusesBadLinesWithTheReason) {
  WindowAssembler a(0.5);
  LineMessage m = line(0, 0.0, 4);
  m.t_s[2] = std::nan("");
  EXPECT_NE(a.add(m).find("time not finite"), std::string::npos);
  m = line(0, 0.0, 4);
  m.range_m.pop_back();
  EXPECT_NE(a.add(m).find("4 pulses but arrays"), std::string::npos);
  m = line(0, 0.0, 4);
  m.t_s[3] = 0.0;
  EXPECT_NE(a.add(m).find("backwards"), std::string::npos);
  m = line(0, 0.0, 4);
  m.azimuth_rad[1] = 7.0;
  EXPECT_NE(a.add(m).find("angle"), std::string::npos);
  m = line(0, 0.0, 4);
  m.range_m[1] = -1.0;
  EXPECT_NE(a.add(m).find("range"), std::string::npos);
  m = line(0, 0.0, 0);
  EXPECT_NE(a.add(m).find("no pulses"), std::string::npos);
  m = line(0, 0.0, 4);
  m.num_pulses = -3;
  EXPECT_FALSE(a.add(m).empty());
  EXPECT_EQ(a.refused(), 7);
  // A miss (NaN range) is a valid pulse.
  m = line(0, 0.0, 4);
  m.range_m[0] = std::nan("");
  EXPECT_EQ(a.add(m), "");
  EXPECT_EQ(a.flush().size(), 1u);
}

// Found by fuzz_sphere_scan_line (its corpus keeps the inputs): a line
// counter with a bit flipped, far from its window's others, made the count
// of missing lines overflow int (negative); a time of 1e300 s made the window
// index leave int64's range (UB).
TEST(WindowAssembler, CorruptCountersAndTimesDoNotOverflow) {
  WindowAssembler a(0.5);
  EXPECT_EQ(a.add(line(0, 0.0, 10)), "");
  EXPECT_EQ(a.add(line(int64_t{1} << 62, 0.1, 10)), "");
  EXPECT_EQ(a.add(line(INT64_MAX, 0.2, 10)), "");
  EXPECT_EQ(a.add(line(INT64_MIN, 0.3, 10, 0, true)), "");
  a.add(line(5, 0.6, 10, 1));
  const auto done = a.take_complete();
  ASSERT_EQ(done.size(), 1u);
  EXPECT_EQ(done[0].lines_received, 4);
  EXPECT_EQ(done[0].lines_missing, INT32_MAX);  // saturated

  WindowAssembler b(0.5);
  LineMessage far = line(0, 0.0, 2);
  far.t_s[1] = 1e300;
  EXPECT_NE(b.add(far).find("time beyond"), std::string::npos);
  far.t_s[1] = WindowAssembler::kMaxScanTimeS;
  EXPECT_EQ(b.add(far), "");
}

TEST(WindowAssembler, RefusesANonsenseWindowLength) {
  EXPECT_THROW(WindowAssembler(0.0), std::invalid_argument);
  EXPECT_THROW(WindowAssembler(std::nan("")), std::invalid_argument);
}

}  // namespace
}  // namespace ephor::sphere
