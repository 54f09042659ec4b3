#include "common/launch/usage_log.h"

#include <gtest/gtest.h>

namespace ephor::launcher {
namespace {

constexpr int64_t kMb = 1024 * 1024;

const UsageSummary& find(const std::vector<UsageSummary>& all, const std::string& name) {
  for (const auto& s : all)
    if (s.name == name) return s;
  throw std::runtime_error("no summary for " + name);
}

TEST(UsageLog, ALeakShowsAsGrowthAfterTheWarmUpAndASteadyProcessAsNone) {
  UsageLog log(/*warmup_s=*/60.0);
  for (int i = 0; i <= 30; ++i) {
    const double t = 10.0 * i;
    // Start-up: 50 MB in the first minute, then steady at 80 MB.
    log.add("steady", t, 5.0, t < 60.0 ? 50 * kMb : 80 * kMb);
    // 1 MB every 10 s from 40 MB: 360 MB per hour.
    log.add("leaky", t, 5.0, 40 * kMb + i * kMb);
  }
  const auto all = log.summaries();
  ASSERT_EQ(all.size(), 2u);
  const auto& steady = find(all, "steady");
  ASSERT_TRUE(steady.rss_growth_bytes_per_hour.has_value());
  EXPECT_NEAR(*steady.rss_growth_bytes_per_hour, 0.0, 1.0) << "the start-up is not a leak";
  EXPECT_EQ(steady.rss_first_bytes, 80 * kMb);
  EXPECT_EQ(steady.rss_max_bytes, 80 * kMb);
  const auto& leaky = find(all, "leaky");
  ASSERT_TRUE(leaky.rss_growth_bytes_per_hour.has_value());
  EXPECT_NEAR(*leaky.rss_growth_bytes_per_hour / kMb, 360.0, 1e-6);
  EXPECT_EQ(leaky.rss_first_bytes, 46 * kMb);
  EXPECT_EQ(leaky.rss_last_bytes, 70 * kMb);
}

TEST(UsageLog, CpuTimeIntegratesThePercentOverEachInterval) {
  UsageLog log(0.0);
  log.add("p", 0.0, 0.0, kMb);    // a first sample has no interval
  log.add("p", 10.0, 50.0, kMb);  // half a CPU for 10 s
  log.add("p", 30.0, 25.0, kMb);  // a quarter for 20 s
  const auto s = log.summaries().at(0);
  EXPECT_EQ(s.samples, 3);
  EXPECT_DOUBLE_EQ(s.span_s, 30.0);
  EXPECT_DOUBLE_EQ(s.cpu_s, 10.0);
  EXPECT_NEAR(s.cpu_percent_mean, 100.0 / 3.0, 1e-9);
}

TEST(UsageLog, ARunShorterThanTheWarmUpHasNoGrowthFigure) {
  UsageLog log(60.0);
  for (int i = 0; i < 5; ++i) log.add("p", i, 1.0, (10 + i) * kMb);
  const auto s = log.summaries().at(0);
  EXPECT_FALSE(s.rss_growth_bytes_per_hour.has_value());
  EXPECT_EQ(s.rss_first_bytes, 10 * kMb) << "without a settled sample, the first one";
  const auto j = to_json(log);
  EXPECT_TRUE(j["processes"][0]["rss_growth_mb_per_hour"].is_null());
  EXPECT_DOUBLE_EQ(j["processes"][0]["rss_max_mb"].get<double>(), 14.0);
  const auto table = format_table(log);
  ASSERT_EQ(table.size(), 2u);
  EXPECT_NE(table[1].find(" - "), std::string::npos) << table[1];
}

}  // namespace
}  // namespace ephor::launcher
