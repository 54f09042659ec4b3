// Fuzz target (issue 18): ephor-monitor's handlers on any stream of the six
// channels it listens to (GROUND_TRUTH, BLOBS, OBJECTS, ARM_GOAL, ARM_CMD,
// EPHOR_SCHED_STATUS): each message decoded as the bus does (one that does not
// decode to its full size is dropped), fed through MonitorFeed as main.cc
// feeds it, on a wall clock that moves by 0-262 ms a message; between
// messages now and then, and at the end, the status line, the events and the
// summary written as JSON text, as the process does at exit. The summary
// must be written whatever the messages said (strings on the wire are any
// bytes), its rates finite and not negative, its latency p50 not above p99,
// and it may count no more arm commands than ARM_CMD messages were fed.
//
// Input: a FuzzMessageStream (common/fuzz/fuzz_input.h) of up to 256
// messages of up to 4096 bytes, channels in the order above. Seeds:
// fuzz_corpus/shepherd_monitor (a frame's truth, blobs, objects, a goal,
// a command sent twice and a scheduler status; a truth with an escape).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "common/fuzz/fuzz_input.h"
#include "common/log/json_text.h"
#include "procs/shared/monitor/monitor_feed.h"
#include "procs/shared/monitor/run_monitor.h"

namespace {

using namespace ephor;

void check(const monitor::RunMonitor& mon, int64_t now_us, int64_t commands_fed) {
  const monitor::Summary s = mon.summary(now_us);
  const std::string text = json_text(s.to_json(), 2);
  if (text.empty()) fuzz::fail("an empty summary");
  (void)mon.status_line(now_us);
  for (const double hz : {s.vision_rate_hz, s.objects_rate_hz})
    if (!std::isfinite(hz) || hz < 0) fuzz::fail("a rate that is not finite or is negative");
  if (s.latency_samples > 0 && !(s.latency_p50_ms <= s.latency_p99_ms))
    fuzz::fail("latency p50 above p99");
  if (s.arm_commands > commands_fed) fuzz::fail("more arm commands counted than were sent");
  if (s.id_switches < 0) fuzz::fail("a negative id switch count");
  if (s.deadline_misses < 0) fuzz::fail("a negative deadline miss count");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  monitor::RunMonitor mon("shepherd");
  monitor::MonitorFeed feed(mon);
  int64_t now_us = 1'700'000'000'000'000;
  int64_t commands_fed = 0;
  fuzz::FuzzMessageStream stream(data, size, 6);
  fuzz::FuzzMessage msg;
  for (int k = 0; stream.next(msg); ++k) {
    now_us += msg.step_us;
    switch (msg.channel) {
      case 0: {
        shepherd_ground_truth_t m;
        if (msg.decode(m)) feed.on_truth(m);
        break;
      }
      case 1: {
        shepherd_blobs_t m;
        if (msg.decode(m)) feed.on_blobs(m, now_us);
        break;
      }
      case 2: {
        shepherd_objects_t m;
        if (msg.decode(m)) feed.on_objects(m, now_us);
        break;
      }
      case 3: {
        arm_goal_t m;
        if (msg.decode(m)) feed.on_arm_goal(m);
        break;
      }
      case 4: {
        arm_cmd_t m;
        if (msg.decode(m)) {
          ++commands_fed;
          feed.on_arm_cmd(m);
        }
        break;
      }
      default: {
        sched_status_t m;
        if (msg.decode(m)) feed.on_sched_status(m);
        break;
      }
    }
    if (k % 16 == 15) {
      (void)mon.take_events();
      check(mon, now_us, commands_fed);
    }
  }
  (void)mon.take_events();
  check(mon, now_us, commands_fed);
  return 0;
}
