// Fuzz target (issue 18): ephor-stripe-display's handlers on any stream of
// the channels it listens to (STRIPE_SCAN, STRIPE_POINTS, STRIPE_CLOUD;
// STRIPE_CAMERA only feeds the DisplayServer's JPEG): each message decoded
// as the bus does (one that does not decode to its full size is dropped)
// and fed through StripeDisplayFeed as main.cc feeds it. The display keeps
// no clock; the stream's clock steps are not used. Now and then, and at the
// end, GET /api/state's system part and GET /api/cloud are built and
// written as json_text, as the DisplayServer serves them: each must be
// built and written without an exception, read back as JSON, and every
// number in it finite (the page draws numbers; nlohmann would write NaN and
// infinities as null); the cloud must hold no more points than the current
// scan's STRIPE_POINTS messages carried.
//
// Input: a FuzzMessageStream (common/fuzz/fuzz_input.h) of up to 256
// messages of up to 4096 bytes, channels in the order above. Seeds:
// fuzz_corpus/stripe_display (a scan running, its stripes' points, then done
// with its cloud; a scan that failed, then a new scan id).
#include <cstddef>
#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include "common/fuzz/fuzz_input.h"
#include "common/fuzz/json_checks.h"
#include "common/log/json_text.h"
#include "procs/stripe/display/stripe_display_feed.h"

namespace {

using namespace ephor;

void check_json(const nlohmann::json& j, const char* what) {
  if (const std::string at = fuzz::first_non_finite(j); !at.empty())
    fuzz::fail(std::string("a number that is not finite in ") + what + " at " + at + ": " +
               json_text(j));
  const std::string text = json_text(j);
  if (!nlohmann::json::accept(text)) fuzz::fail(std::string(what) + " text that is not JSON");
}

void check(const stripe_display::StripeDisplayFeed& feed, size_t points_fed) {
  check_json(feed.state(), "the state");
  const nlohmann::json cloud = feed.cloud();
  check_json(cloud, "the cloud");
  if (cloud["points"].get<size_t>() > points_fed) fuzz::fail("more points than were sent");
  if (cloud["xyz"].size() != 3 * cloud["points"].get<size_t>()) fuzz::fail("xyz not 3 a point");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  stripe_display::StripeDisplayFeed feed;
  size_t points_fed = 0;  // since the scan id last changed
  int64_t scan_id = 0;
  bool have_scan = false;
  fuzz::FuzzMessageStream stream(data, size, 3);
  fuzz::FuzzMessage msg;
  for (int k = 0; stream.next(msg); ++k) {
    switch (msg.channel) {
      case 0: {
        stripe_scan_t m;
        if (msg.decode(m)) {
          if (!have_scan || m.scan_id != scan_id) points_fed = 0;
          have_scan = true;
          scan_id = m.scan_id;
          feed.on_scan(m);
        }
        break;
      }
      case 1: {
        stripe_points_t m;
        if (msg.decode(m)) {
          points_fed += m.x_mm.size();
          feed.on_points(m);
        }
        break;
      }
      default: {
        stripe_cloud_t m;
        if (msg.decode(m)) feed.on_cloud(m);
        break;
      }
    }
    if (k % 8 == 7) check(feed, points_fed);
  }
  check(feed, points_fed);
  return 0;
}
