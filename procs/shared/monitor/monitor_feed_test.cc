#include "procs/shared/monitor/monitor_feed.h"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

namespace ephor::monitor {
namespace {

constexpr int64_t kT0 = 1'700'000'000'000'000;

arm_cmd_t command(const char* sender, int64_t seq) {
  arm_cmd_t c{};
  c.header.sender = sender;
  c.header.utime = kT0 + 5000;
  c.seq = seq;
  c.source_frame_utime = kT0;
  return c;
}

sched_status_t status(const char* host, bool rt, int64_t misses) {
  sched_status_t s{};
  s.host = host;
  s.rt = rt;
  task_status_t t{};
  t.deadline_misses = misses;
  s.tasks = {t};
  s.num_tasks = 1;
  return s;
}

TEST(MonitorFeed, CountsACommandSentAgainOnce) {
  RunMonitor mon("test");
  MonitorFeed feed(mon);
  feed.on_arm_cmd(command("comm", 1));
  feed.on_arm_cmd(command("comm", 1));  // comm's retransmission
  feed.on_arm_cmd(command("comm", 2));
  feed.on_arm_cmd(command("comm2", 1));  // another sender's seq 1 is another command
  EXPECT_EQ(mon.summary(kT0).arm_commands, 3);
}

TEST(MonitorFeed, RunIsRealTimeOnlyWhenEveryHostIs) {
  RunMonitor mon("test");
  MonitorFeed feed(mon);
  feed.on_sched_status(status("a", true, 2));
  feed.on_sched_status(status("b", false, 3));
  EXPECT_FALSE(mon.summary(kT0).rt);
  EXPECT_EQ(mon.summary(kT0).deadline_misses, 5);
  feed.on_sched_status(status("b", true, 3));  // the host's newest status replaces its last
  EXPECT_TRUE(mon.summary(kT0).rt);
  EXPECT_EQ(mon.summary(kT0).deadline_misses, 5);
}

// Counts from the wire: a corrupt one must not overflow the sum (undefined
// behaviour) nor make it negative.
TEST(MonitorFeed, DeadlineMissesFromTheWireSaturate) {
  RunMonitor mon("test");
  MonitorFeed feed(mon);
  feed.on_sched_status(status("a", true, std::numeric_limits<int64_t>::max()));
  feed.on_sched_status(status("b", true, 5));
  feed.on_sched_status(status("c", true, -9));
  EXPECT_EQ(mon.summary(kT0).deadline_misses, std::numeric_limits<int64_t>::max());
}

// Two messages received in the same microsecond (a burst after a stall) made
// the rate 1/0 (seen while writing the shepherd_monitor fuzz target, whose
// check asks for finite rates).
TEST(MonitorFeed, RateOfMessagesInOneMicrosecondIsNotInfinite) {
  RunMonitor mon("test");
  MonitorFeed feed(mon);
  shepherd_blobs_t b{};
  b.utime = kT0;
  feed.on_blobs(b, kT0 + 1000);
  feed.on_blobs(b, kT0 + 1000);
  const double hz = mon.summary(kT0 + 1000).vision_rate_hz;
  EXPECT_TRUE(std::isfinite(hz));
}

}  // namespace
}  // namespace ephor::monitor
