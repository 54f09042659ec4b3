#include "common/runtime/rolling_stats.h"

#include <gtest/gtest.h>

namespace ephor {
namespace {

TEST(RollingStats, EmptyIsZero) {
  RollingStats s(10);
  EXPECT_TRUE(s.empty());
  EXPECT_EQ(s.percentile(50), 0.0);
  EXPECT_EQ(s.max(), 0.0);
}

TEST(RollingStats, NearestRankPercentiles) {
  RollingStats s(1000);
  for (int i = 1; i <= 100; ++i) s.add(i);  // 1..100
  EXPECT_EQ(s.percentile(50), 50.0);
  EXPECT_EQ(s.percentile(99), 99.0);
  EXPECT_EQ(s.percentile(100), 100.0);
  EXPECT_EQ(s.percentile(0), 1.0);
  EXPECT_EQ(s.max(), 100.0);
}

TEST(RollingStats, KeepsOnlyNewestCapacitySamples) {
  RollingStats s(3);
  for (double v : {100.0, 1.0, 2.0, 3.0}) s.add(v);
  EXPECT_EQ(s.size(), 3u);
  EXPECT_EQ(s.max(), 3.0);  // 100 fell out of the window
}

TEST(RollingStats, MaxOfNewestIsThePapersThreeRunEstimate) {
  RollingStats s(100);
  for (double v : {9.0, 1.0, 2.0, 3.0}) s.add(v);
  EXPECT_EQ(s.max_of_newest(3), 3.0);
  EXPECT_EQ(s.max_of_newest(4), 9.0);
  EXPECT_EQ(s.max_of_newest(50), 9.0);
}

}  // namespace
}  // namespace ephor
