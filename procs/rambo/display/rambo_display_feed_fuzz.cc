// Fuzz target (issue 18): ephor-rambo-display's handlers on any stream of
// the channels it listens to (RAMBO_FEATURES, RAMBO_POSE, RAMBO_TRUTH,
// RAMBO_PLAN, RAMBO_INDICATOR, ARM_STATE; RAMBO_PREDICTION has no handler):
// each message decoded as the bus does (one that does not decode to its full
// size is dropped) and fed through RamboDisplayFeed as main.cc feeds it,
// with the built-in target and its diodes (no --model, no --diodes, as
// deploy/rambo.pbtxt runs it). The messages carry their own times; the
// clock steps of the stream are not used. Now and then, and at the end, GET
// /api/state's system part is built and written as json_text, as the
// DisplayServer serves it: it must be built and written without an
// exception, read back as JSON, and every number in it finite (the page
// draws numbers; nlohmann would write NaN and infinities as null).
//
// Input: a FuzzMessageStream (common/fuzz/fuzz_input.h) of up to 256
// messages of up to 4096 bytes, channels in the order above. Seeds:
// fuzz_corpus/rambo_display (a frame's features, the pose found and the
// truth of that frame, the plan, the indicator with a diode tagged, the
// arm's joints; a pose not found).
#include <cstddef>
#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include "common/fuzz/fuzz_input.h"
#include "common/fuzz/json_checks.h"
#include "common/log/json_text.h"
#include "common/rambo/target_model_file.h"
#include "procs/rambo/display/rambo_display_feed.h"

namespace {

using namespace ephor;

void check(const rambo_display::RamboDisplayFeed& feed) {
  const nlohmann::json j = feed.state();
  if (const std::string at = fuzz::first_non_finite(j); !at.empty())
    fuzz::fail("a number that is not finite in the state at " + at + ": " + json_text(j));
  const std::string text = json_text(j);
  if (!nlohmann::json::accept(text)) fuzz::fail("state text that is not JSON: " + text);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const rambo::RamboCell cell = rambo::cell_from_flags("", 0);
  rambo_display::RamboDisplayFeed feed(cell);
  fuzz::FuzzMessageStream stream(data, size, 6);
  fuzz::FuzzMessage msg;
  for (int k = 0; stream.next(msg); ++k) {
    switch (msg.channel) {
      case 0: {
        rambo_features_t m;
        if (msg.decode(m)) feed.on_features(m);
        break;
      }
      case 1: {
        rambo_pose_t m;
        if (msg.decode(m)) feed.on_pose(m);
        break;
      }
      case 2: {
        rambo_truth_t m;
        if (msg.decode(m)) feed.on_truth(m);
        break;
      }
      case 3: {
        rambo_plan_t m;
        if (msg.decode(m)) feed.on_plan(m);
        break;
      }
      case 4: {
        rambo_indicator_t m;
        if (msg.decode(m)) feed.on_indicator(m);
        break;
      }
      default: {
        arm_state_t m;
        if (msg.decode(m)) feed.on_arm_state(m);
        break;
      }
    }
    if (k % 8 == 7) check(feed);
  }
  check(feed);
  return 0;
}
