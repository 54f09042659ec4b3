#include "common/display/sched_table.h"

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

TEST(SchedTableTest, NoStatusIsAnEmptyArray) {
  const auto j = SchedTable{}.to_json();
  EXPECT_TRUE(j.is_array());
  EXPECT_TRUE(j.empty());
}

}  // namespace
}  // namespace ephor::display
