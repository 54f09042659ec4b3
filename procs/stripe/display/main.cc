// ephor-stripe-display: the light-stripe system's live page (issue 16): the
// scan's cloud growing stripe by stripe in a 3-D view (three.js, served by
// every display from Debian's libjs-three at /lib/three.min.js) beside the
// camera's newest image, with the scan's state, on the shared DisplayServer
// (common/display); StripeDisplayFeed keeps the state and builds the JSON.
//
//   ephor-stripe-display [--http-address 127.0.0.1] [--http-port 8084]
//
//   subscribes  STRIPE_SCAN, STRIPE_POINTS, STRIPE_CLOUD, STRIPE_CAMERA (the images as
//               camera_frame_t, for /api/frame.jpg), EPHOR_SCHED_STATUS
//   serves      / (the page), /api/state (the scan, the cloud's size), /api/cloud (the
//               current scan's points, mm, table frame), /api/frame.jpg

#include <string>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include "common/display/display_server.h"
#include "common/display/lcm_json.h"
#include "common/lcm/bus.h"
#include "common/log/log.h"
#include "common/runtime/process_args.h"
#include "common/stripe/stripe_channels.h"
#include "common/time/clock.h"
#include "ephor/stripe_cloud_t.hpp"
#include "ephor/stripe_points_t.hpp"
#include "ephor/stripe_scan_t.hpp"
#include "procs/stripe/display/stripe_display_feed.h"
#include "procs/stripe/display/stripe_web_assets.h"

namespace ephor {
EPHOR_TO_JSON(stripe_scan_t, utime, header, scan_id, state, reason, region_mm, step_mm, height_mm,
              stripes_along_y, stripes_planned, stripes_captured, stripes_skipped, elapsed_s,
              stripes_per_s, motion_s, cloud_points)
EPHOR_TO_JSON(stripe_cloud_t, utime, header, scan_id, stripes, stripes_missing, points, path, error,
              bbox_mm)
void to_json(nlohmann::json& j, const stripe_points_t& m) {
  j = {{"utime", m.utime},
       {"scan_id", m.scan_id},
       {"stripe_index", m.stripe_index},
       {"num_points", m.num_points},
       {"scan_points", m.scan_points}};
}
}  // namespace ephor

int main(int argc, char** argv) {
  using namespace ephor;
  block_shutdown_signals();
  CLI::App app{"ephor-stripe-display: live web page of the light-stripe system"};
  ProcessArgs args;
  add_process_flags(app, args, "display");
  display::DisplayServerOptions options;
  options.http_port = 8084;
  options.camera_channel = stripe::channels::kCamera;
  options.estop = true;
  app.add_option("--http-address", options.http_address,
                 "address to serve the page on (default loopback)");
  app.add_option("--http-port", options.http_port, "TCP port of the page (default 8084)")
      ->check(CLI::Range(1, 65535));
  if (const auto exit_status = ephor::parse_flags(app, argc, argv)) return *exit_status;
  init_logging(args.name);
  try {
    Bus bus(args.lcm_url, args.name);
    stripe_display::StripeDisplayFeed feed;
    display::DisplayServer server(bus, options, &stripe_display::find_web_asset);
    server.subscribe<stripe_scan_t>(stripe::channels::kScan,
                                    [&](const stripe_scan_t& m) { feed.on_scan(m); });
    server.subscribe<stripe_points_t>(stripe::channels::kPoints,
                                      [&](const stripe_points_t& m) { feed.on_points(m); });
    server.subscribe<stripe_cloud_t>(stripe::channels::kCloud,
                                     [&](const stripe_cloud_t& m) { feed.on_cloud(m); });
    server.set_state_builder([&](int64_t) { return feed.state(); });
    server.add_json_route("/api/cloud", [&](int64_t) { return feed.cloud(); });
    server.run("stripe display");
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
  return 0;
}
