// ephor-sphere-display: the sphere system's live web page (paper 002; issue
// 15): the newest half-second raster of the range finder coloured by range,
// the locator's estimate, the guidance's filtered sphere with its 1-sigma
// ellipse, the ground truth, and the approach (range and offset from the
// boresight over time, phase, capture verdict). Only listens: no commands
// (the system has no arm to stop). DisplayServer serves it; SphereDisplayFeed
// converts the messages for SphereDisplayState and builds the state.
//
//   ephor-sphere-display [--http-address 127.0.0.1] [--http-port 8082] [--capture-m 1]
//
//   subscribes  SPHERE_SCAN_LINE, SPHERE_ESTIMATE, SPHERE_GUIDANCE, SPHERE_TRUTH,
//               EPHOR_SCHED_STATUS
//   serves      GET /api/state (no raster points), GET /api/scan (the raster),
//               /api/debug, /api/rates (DisplayServer)

#include <cmath>
#include <string>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include "common/display/display_server.h"
#include "common/lcm/bus.h"
#include "common/log/log.h"
#include "common/runtime/process_args.h"
#include "common/sphere/sphere_channels.h"
#include "common/time/clock.h"
#include "procs/sphere/display/sphere_display_feed.h"
#include "procs/sphere/display/sphere_lcm_json.h"
#include "procs/sphere/display/sphere_web_assets.h"

namespace {

using namespace ephor;
using namespace ephor::sphere_display;

void subscribe_all(display::DisplayServer& server, SphereDisplayFeed& feed) {
  server.subscribe<sphere_scan_line_t>(
      sphere::channels::kScanLine,
      [&](const sphere_scan_line_t& m) { feed.on_scan_line(m, wall_us()); });
  server.subscribe<sphere_estimate_t>(sphere::channels::kEstimate, [&](const sphere_estimate_t& m) {
    feed.on_estimate(m, wall_us());
  });
  server.subscribe<sphere_guidance_t>(sphere::channels::kGuidance, [&](const sphere_guidance_t& m) {
    feed.on_guidance(m, wall_us());
  });
  server.subscribe<sphere_truth_t>(sphere::channels::kTruth,
                                   [&](const sphere_truth_t& m) { feed.on_truth(m, wall_us()); });
}

}  // namespace

int main(int argc, char** argv) {
  block_shutdown_signals();
  CLI::App app{"ephor-sphere-display: live web page of the sphere system"};
  ProcessArgs args;
  add_process_flags(app, args, "display");
  display::DisplayServerOptions server_options;
  server_options.http_port = 8082;
  SphereDisplayOptions options;
  app.add_option("--http-address", server_options.http_address,
                 "address to serve the page on (default loopback)");
  app.add_option("--http-port", server_options.http_port, "TCP port of the page (default 8082)")
      ->check(CLI::Range(1, 65535));
  app.add_option("--capture-m", options.capture_distance_m,
                 "capture distance drawn on the approach plot, m (default 1, the ranger's)")
      ->check(CLI::Range(0.1, 100.0));
  if (const auto exit_status = ephor::parse_flags(app, argc, argv)) return *exit_status;
  init_logging(args.name);
  if (!std::isfinite(options.capture_distance_m)) {  // CLI::Range lets NaN through
    spdlog::error("--capture-m must be a number of metres in 0.1..100");
    return 1;
  }

  try {
    Bus bus(args.lcm_url, args.name);
    SphereDisplayFeed feed(options);
    display::DisplayServer server(bus, server_options, &find_web_asset);
    subscribe_all(server, feed);
    server.set_state_builder([&](int64_t now_us) { return feed.state(now_us); });
    server.add_json_route("/api/scan", [&](int64_t) { return feed.scan(); });
    server.run("sphere display");
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
  return 0;
}
