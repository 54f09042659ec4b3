// Fuzz target (issue 18): ephor-catch-monitor's handlers on any stream of the
// four channels it listens to (CATCH_TRUTH, CATCH_WORLD, CATCH_BOARD_POSE,
// EPHOR_SCHED_STATUS): each message decoded as the bus does (one that does
// not decode to its full size is dropped) and fed through CatchMonitorFeed as
// main.cc feeds it; now and then, and at the end, the status line and the
// summary written as JSON text, as the process does at exit. The summary
// must be written whatever the messages said (strings on the wire are any
// bytes: a reason, a host, a task name), and it may not count more catches
// than balls.
//
// Input: a FuzzMessageStream (common/fuzz/fuzz_input.h) of up to 256
// messages of up to 4096 bytes, channels in the order above. Seeds:
// fuzz_corpus/catch_monitor (a board pose, a ball rolling, tracked and
// caught, a scheduler status).
#include <cstddef>
#include <cstdint>
#include <string>

#include "common/fuzz/fuzz_input.h"
#include "common/log/json_text.h"
#include "procs/catch/monitor/catch_monitor_feed.h"

namespace {

using namespace ephor;
using namespace ephor::catching;

void check(const CatchSummary& summary) {
  (void)summary.status_line();
  const nlohmann::json j = summary.to_json();
  if (json_text(j, 2).empty()) fuzz::fail("an empty summary");
  if (summary.caught() > summary.balls()) fuzz::fail("more catches than balls");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  CatchSummary summary(1);
  CatchMonitorFeed feed(summary);
  fuzz::FuzzMessageStream stream(data, size, 4);
  fuzz::FuzzMessage msg;
  for (int k = 0; stream.next(msg); ++k) {
    switch (msg.channel) {
      case 0: {
        catch_truth_t m;
        if (msg.decode(m)) (void)feed.on_truth(m);
        break;
      }
      case 1: {
        catch_world_t m;
        if (msg.decode(m)) feed.on_world(m);
        break;
      }
      case 2: {
        catch_board_pose_t m;
        if (msg.decode(m)) feed.on_board_pose(m);
        break;
      }
      default: {
        sched_status_t m;
        if (msg.decode(m)) feed.on_sched_status(m);
        break;
      }
    }
    if (k % 16 == 15) check(summary);
  }
  check(summary);
  return 0;
}
