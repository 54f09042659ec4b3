#include "procs/shared/monitor/run_monitor.h"

#include <gtest/gtest.h>

namespace ephor::monitor {
namespace {

Truth truth_at(int64_t utime, double x, double y, bool visible = true) {
  Truth t;
  t.utime = utime;
  t.sheep.push_back({1, x, y, x / 2, y / 2, visible, true});
  t.sim_time_s = static_cast<double>(utime) * 1e-6;
  return t;
}

TrackedObject obj(int32_t id, double x, double y) {
  TrackedObject o;
  o.id = id;
  o.x_mm = x;
  o.y_mm = y;
  o.u = x / 2;
  o.v = y / 2;
  return o;
}

TEST(RunMonitor, CountsAnIdSwitchWhenTheMatchedObjectChanges) {
  RunMonitor m("test");
  m.on_truth(truth_at(1000, 100, 100));
  m.on_objects(1000, 0, {obj(7, 102, 100)}, 1000);
  m.on_truth(truth_at(2000, 110, 100));
  m.on_objects(2000, 0, {obj(7, 111, 100)}, 2000);
  EXPECT_EQ(m.summary(2000).id_switches, 0);
  m.on_truth(truth_at(3000, 120, 100));
  m.on_objects(3000, 0, {obj(9, 120, 101)}, 3000);  // same sheep, new id
  EXPECT_EQ(m.summary(3000).id_switches, 1);
  // The log says which sheep, where, and that object 7 vanished.
  const auto events = m.take_events();
  ASSERT_EQ(events.size(), 1u);
  EXPECT_NE(events[0].find("sheep"), std::string::npos) << events[0];
  EXPECT_NE(events[0].find("was object 7 (gone from OBJECTS), now object 9"), std::string::npos)
      << events[0];
  EXPECT_TRUE(m.take_events().empty());
}

TEST(RunMonitor, SaysWhichSheepEscapedAndWhere) {
  RunMonitor m("test");
  m.on_truth(truth_at(1000, 5, 300));
  EXPECT_TRUE(m.take_events().empty());
  Truth gone = truth_at(2000, -3, 300);
  gone.sheep[0].on_field = false;
  gone.escapes = 1;
  m.on_truth(gone);
  const auto events = m.take_events();
  ASSERT_EQ(events.size(), 1u);
  EXPECT_NE(events[0].find("escape: sheep 1 left the field at (5, 300) mm"), std::string::npos)
      << events[0];
  m.on_truth(gone);  // still out: said once
  EXPECT_TRUE(m.take_events().empty());
}

TEST(RunMonitor, ASheepThatEscapedAndReenteredIsANewSheep) {
  RunMonitor m("test");
  m.on_truth(truth_at(1000, 100, 100));
  m.on_objects(1000, 0, {obj(7, 100, 100)}, 1000);
  Truth gone = truth_at(2000, -50, 100);
  gone.sheep[0].on_field = false;
  m.on_truth(gone);
  m.on_objects(2000, 0, {}, 2000);
  m.on_truth(truth_at(3000, 5, 400));  // back through another edge, same truth id
  m.on_objects(3000, 0, {obj(12, 5, 400)}, 3000);
  EXPECT_EQ(m.summary(3000).id_switches, 0);
  EXPECT_TRUE(m.take_events().empty());
}

TEST(RunMonitor, HiddenSheepAndFarObjectsAreNotMatched) {
  RunMonitor m("test", 40.0);
  m.on_truth(truth_at(1000, 100, 100));
  m.on_objects(1000, 0, {obj(7, 100, 100)}, 1000);
  m.on_truth(truth_at(2000, 100, 100, /*visible=*/false));
  m.on_objects(2000, 0, {obj(8, 100, 100)}, 2000);  // hidden: not scored
  m.on_truth(truth_at(3000, 100, 100));
  m.on_objects(3000, 0, {obj(8, 200, 100)}, 3000);  // 100 mm away: no match
  EXPECT_EQ(m.summary(3000).id_switches, 0);
}

TEST(RunMonitor, LatencyPercentilesInMilliseconds) {
  RunMonitor m("test");
  for (int i = 1; i <= 100; ++i) m.on_arm_command(1'000'000, 1'000'000 + i * 100);  // 0.1 .. 10 ms
  const Summary s = m.summary(0);
  EXPECT_NEAR(s.latency_p50_ms, 5.0, 1e-9);
  EXPECT_NEAR(s.latency_p99_ms, 9.9, 1e-9);
  EXPECT_EQ(s.arm_commands, 100);
}

TEST(RunMonitor, SummaryJsonHasTheDocumentedKeys) {
  RunMonitor m("shepherd");
  m.on_sched_status(true, 3);
  const auto j = m.summary(0).to_json();
  for (const char* key : {"scenario", "duration_s", "sheep", "escapes", "saves", "vision_rate_hz",
                          "latency_ms", "id_switches", "deadline_misses", "rt"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_EQ(j["deadline_misses"], 3);
  EXPECT_EQ(j["rt"], true);
  EXPECT_TRUE(j["latency_ms"].contains("p99"));
}

}  // namespace
}  // namespace ephor::monitor
