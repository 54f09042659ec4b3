#include "common/runtime/periodic_release.h"

#include <gtest/gtest.h>

namespace ephor {
namespace {

constexpr int64_t kMs = 1'000'000;

TEST(PeriodicRelease, OnTimeJobsAdvanceByOnePeriod) {
  PeriodicRelease r(1000 * kMs, 10 * kMs);
  EXPECT_EQ(r.next_release_ns(), 1000 * kMs);
  EXPECT_EQ(r.advance(1002 * kMs), 0);
  EXPECT_EQ(r.next_release_ns(), 1010 * kMs);
  EXPECT_EQ(r.advance(1019 * kMs), 0);
  EXPECT_EQ(r.next_release_ns(), 1020 * kMs);
}

TEST(PeriodicRelease, OverrunLessThanAPeriodStartsLateWithoutSkipping) {
  PeriodicRelease r(0, 10 * kMs);
  // Job released at 0 ends at 15 ms: release 10 ms has passed but not by a
  // whole period, so the next job starts at once with 5 ms latency.
  EXPECT_EQ(r.advance(15 * kMs), 0);
  EXPECT_EQ(r.next_release_ns(), 10 * kMs);
}

TEST(PeriodicRelease, LongOverrunSkipsWholePeriods) {
  PeriodicRelease r(0, 10 * kMs);
  // Ends at 37 ms: releases at 10 and 20 ms are stale, 30 ms is the newest.
  EXPECT_EQ(r.advance(37 * kMs), 2);
  EXPECT_EQ(r.next_release_ns(), 30 * kMs);
}

TEST(PeriodicRelease, PeriodChangeKeepsPhase) {
  PeriodicRelease r(0, 10 * kMs);
  r.advance(1 * kMs);
  r.set_period(25 * kMs);
  EXPECT_EQ(r.next_release_ns(), 10 * kMs);
  r.advance(11 * kMs);
  EXPECT_EQ(r.next_release_ns(), 35 * kMs);
}

TEST(PeriodicRelease, AlignLocksThePhaseToAnAnchor) {
  PeriodicRelease r(0, 10 * kMs);
  // A frame arrived at 23.5 ms; the job ended at 25 ms: next release 33.5 ms.
  r.align(23'500'000, 25 * kMs);
  EXPECT_EQ(r.next_release_ns(), 33'500'000);
  // An anchor in the future (the frame expected 4 ms from now) is used as is.
  r.align(40 * kMs, 36 * kMs);
  EXPECT_EQ(r.next_release_ns(), 40 * kMs);
  // An old anchor: the first phase-aligned release after now.
  r.align(1 * kMs, 95 * kMs);
  EXPECT_EQ(r.next_release_ns(), 101 * kMs);
}

TEST(PeriodicRelease, RejectsNonPositivePeriod) {
  EXPECT_THROW(PeriodicRelease(0, 0), std::invalid_argument);
  PeriodicRelease r(0, 1);
  EXPECT_THROW(r.set_period(-5), std::invalid_argument);
}

}  // namespace
}  // namespace ephor
