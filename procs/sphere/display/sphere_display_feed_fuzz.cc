// Fuzz target (issue 18): ephor-sphere-display's handlers on any stream of
// the channels it listens to (SPHERE_SCAN_LINE, SPHERE_ESTIMATE,
// SPHERE_GUIDANCE, SPHERE_TRUTH): each message decoded as the bus does (one
// that does not decode to its full size is dropped) and fed through
// SphereDisplayFeed as main.cc feeds it, with the default options (capture
// at 1 m), on a wall clock that moves by 0-262 ms a message. Now and then,
// and at the end, GET /api/state's system part and GET /api/scan are built
// and written as json_text, as the DisplayServer serves them: each must be
// built and written without an exception, read back as JSON, and every
// number in it finite (the page draws numbers; nlohmann would write NaN and
// infinities as null).
//
// Input: a FuzzMessageStream (common/fuzz/fuzz_input.h) of up to 256
// messages of up to 4096 bytes, channels in the order above. Seeds:
// fuzz_corpus/sphere_display (a window's scan lines with returns and
// misses, the estimate, the guidance and the truth of an approach, then its
// capture; an estimate that failed).
#include <cstddef>
#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include "common/fuzz/fuzz_input.h"
#include "common/fuzz/json_checks.h"
#include "common/log/json_text.h"
#include "procs/sphere/display/sphere_display_feed.h"

namespace {

using namespace ephor;

void check_json(const nlohmann::json& j, const char* what) {
  if (const std::string at = fuzz::first_non_finite(j); !at.empty())
    fuzz::fail(std::string("a number that is not finite in ") + what + " at " + at + ": " +
               json_text(j));
  const std::string text = json_text(j);
  if (!nlohmann::json::accept(text)) fuzz::fail(std::string(what) + " text that is not JSON");
}

void check(const sphere_display::SphereDisplayFeed& feed, int64_t now_us) {
  check_json(feed.state(now_us), "the state");
  check_json(feed.scan(), "the scan");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  sphere_display::SphereDisplayFeed feed;
  int64_t now_us = 1'700'000'000'000'000;
  fuzz::FuzzMessageStream stream(data, size, 4);
  fuzz::FuzzMessage msg;
  for (int k = 0; stream.next(msg); ++k) {
    now_us += msg.step_us;
    switch (msg.channel) {
      case 0: {
        sphere_scan_line_t m;
        if (msg.decode(m)) feed.on_scan_line(m, now_us);
        break;
      }
      case 1: {
        sphere_estimate_t m;
        if (msg.decode(m)) feed.on_estimate(m, now_us);
        break;
      }
      case 2: {
        sphere_guidance_t m;
        if (msg.decode(m)) feed.on_guidance(m, now_us);
        break;
      }
      default: {
        sphere_truth_t m;
        if (msg.decode(m)) feed.on_truth(m, now_us);
        break;
      }
    }
    if (k % 8 == 7) check(feed, now_us);
  }
  check(feed, now_us);
  return 0;
}
