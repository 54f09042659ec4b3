// Fuzz target (issue 18): what DisplayServer, under every system's page, does
// with the messages every page hears, on any stream of them: each decoded as
// the bus does (one that does not decode to its full size is dropped), kept
// as the channel's newest for the debug dump (NewestMessages, as subscribe<T>
// does), a scheduler status also converted by host_sched_of into the task
// table (SchedTable), a camera frame's fields kept without its pixels; now
// and then, and at the end, the page's task table and the debug dump
// (GET /api/debug's "channels" and "sched") written as JSON text, as the
// server answers them. Both must be written whatever the messages said
// (strings on the wire are any bytes), and the task table, which the page
// draws, must carry only finite numbers.
//
// Input: a FuzzMessageStream (common/fuzz/fuzz_input.h) of up to 256
// messages of up to 4096 bytes; channels: EPHOR_SCHED_STATUS, CAMERA
// (fields), ARM_STATE, ARM_GOAL, ARM_CMD, ARM_ACK, MOTION_DONE, EPHOR_ESTOP.
// Seeds: fuzz_corpus/display_server (two hosts' statuses, an arm's state,
// goal, command, ack and done, a stop and its release).
#include <cstddef>
#include <cstdint>
#include <string>

#include "common/display/lcm_json.h"
#include "common/display/newest_messages.h"
#include "common/display/sched_status_rows.h"
#include "common/display/sched_table.h"
#include "common/fuzz/fuzz_input.h"
#include "common/fuzz/json_checks.h"
#include "common/lcm/channels.h"
#include "common/log/json_text.h"
#include "common/runtime/channels.h"

namespace {

using namespace ephor;

template <typename T>
void keep(display::NewestMessages& newest, const std::string& channel,
          const fuzz::FuzzMessage& msg) {
  T m;
  if (msg.decode(m)) newest.put(channel, m);
}

void check(const display::NewestMessages& newest, const display::SchedTable& table) {
  const nlohmann::json sched = table.to_json();
  if (const std::string at = fuzz::first_non_finite(sched); !at.empty())
    fuzz::fail("a number that is not finite in the task table at " + at);
  nlohmann::json debug;
  debug["channels"] = newest.to_json();
  debug["sched"] = sched;
  if (json_text(debug).empty()) fuzz::fail("an empty debug dump");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  display::NewestMessages newest;
  display::SchedTable table;
  fuzz::FuzzMessageStream stream(data, size, 8);
  fuzz::FuzzMessage msg;
  for (int k = 0; stream.next(msg); ++k) {
    switch (msg.channel) {
      case 0: {
        sched_status_t m;
        if (!msg.decode(m)) break;
        newest.put(channels::kSchedStatus + std::string("/") + m.host, m);
        table.on_sched(display::host_sched_of(m));
        break;
      }
      case 1: {
        camera_frame_t m;
        if (!msg.decode(m)) break;
        newest.put(channels::kCamera, frame_fields(m));
        break;
      }
      case 2:
        keep<arm_state_t>(newest, channels::kArmState, msg);
        break;
      case 3:
        keep<arm_goal_t>(newest, channels::kArmGoal, msg);
        break;
      case 4:
        keep<arm_cmd_t>(newest, channels::kArmCmd, msg);
        break;
      case 5:
        keep<arm_ack_t>(newest, channels::kArmAck, msg);
        break;
      case 6:
        keep<motion_done_t>(newest, channels::kMotionDone, msg);
        break;
      default:
        keep<estop_t>(newest, channels::kEstop, msg);
        break;
    }
    if (k % 16 == 15) check(newest, table);
  }
  check(newest, table);
  return 0;
}
