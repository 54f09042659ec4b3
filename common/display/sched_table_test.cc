#include "common/display/sched_table.h"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

namespace ephor::display {
namespace {

TEST(SchedTableTest, NewestStatusPerHostInNameOrder) {
  SchedTable t;
  HostSched a;
  a.host = "sensor";
  a.tasks.push_back({});
  a.tasks[0].process = "ranger";
  a.tasks[0].task = "scan";
  a.tasks[0].exec_p99_us = 12.34;
  HostSched b;
  b.host = "arm";
  t.on_sched(a);
  t.on_sched(b);
  a.tasks[0].deadline_misses = 3;  // a newer status of the same host replaces the old one
  t.on_sched(a);
  const auto j = t.to_json();
  EXPECT_EQ(t.hosts(), 2u);
  ASSERT_EQ(j.size(), 2u);
  EXPECT_EQ(j[0]["host"], "arm");
  EXPECT_EQ(j[1]["tasks"][0]["task"], "scan");
  EXPECT_NEAR(j[1]["tasks"][0]["exec_p99_us"].get<double>(), 12.3, 1e-9);
  EXPECT_EQ(j[1]["tasks"][0]["deadline_misses"], 3);
}

// A corrupt status's shares (NaN, infinite) are drawn as 0: JSON has no NaN
// (nlohmann would write null, which the page reads as 0 or breaks on).
TEST(SchedTableTest, SharesThatAreNotFiniteAreZero) {
  SchedTable t;
  HostSched a;
  a.host = "sensor";
  a.cpu_utilisation = {std::nan(""), 0.25};
  a.cpu_bound = {std::numeric_limits<double>::infinity()};
  TaskRow row;
  row.utilisation = std::nan("");
  a.tasks.push_back(row);
  t.on_sched(a);
  const auto j = t.to_json();
  EXPECT_EQ(j[0]["cpu_utilisation"][0], 0.0);
  EXPECT_EQ(j[0]["cpu_utilisation"][1], 0.25);
  EXPECT_EQ(j[0]["cpu_bound"][0], 0.0);
  EXPECT_EQ(j[0]["tasks"][0]["utilisation"], 0.0);
}

TEST(SchedTableTest, NoStatusIsAnEmptyArray) {
  const auto j = SchedTable{}.to_json();
  EXPECT_TRUE(j.is_array());
  EXPECT_TRUE(j.empty());
}

}  // namespace
}  // namespace ephor::display
