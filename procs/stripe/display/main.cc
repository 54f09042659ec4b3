// ephor-stripe-display: the light-stripe system's live page (issue 16): the
// scan's cloud growing stripe by stripe in a 3-D view (three.js, served by
// every display from Debian's libjs-three at /lib/three.min.js) beside the
// camera's newest image, with the scan's state, on the shared DisplayServer
// (common/display).
//
//   ephor-stripe-display [--http-address 127.0.0.1] [--http-port 8084]
//
//   subscribes  STRIPE_SCAN, STRIPE_POINTS, STRIPE_CLOUD, STRIPE_CAMERA (the images as
//               camera_frame_t, for /api/frame.jpg), EPHOR_SCHED_STATUS
//   serves      / (the page), /api/state (the scan, the cloud's size), /api/cloud (the
//               current scan's points, mm, table frame), /api/frame.jpg

#include <cmath>
#include <string>
#include <vector>

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

namespace {

using namespace ephor;

const char* state_name(int s) {
  switch (s) {
    case stripe_scan_t::STATE_WAITING:
      return "waiting";
    case stripe_scan_t::STATE_RUNNING:
      return "running";
    case stripe_scan_t::STATE_CAPTURED:
      return "captured";
    case stripe_scan_t::STATE_DONE:
      return "done";
    case stripe_scan_t::STATE_FAILED:
      return "failed";
  }
  return "unknown";
}

// The page's state (the server's lock held by every caller).
struct State {
  bool have_scan = false;
  stripe_scan_t scan{};
  std::vector<float> xyz;  // the current scan's points, mm, table frame
  int stripes = 0;
  bool have_cloud = false;
  stripe_cloud_t cloud{};
};

}  // namespace

int main(int argc, char** argv) {
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
    State s;
    display::DisplayServer server(bus, options, &stripe_display::find_web_asset);
    server.subscribe<stripe_scan_t>(stripe::channels::kScan, [&](const stripe_scan_t& m) {
      if (!s.have_scan || m.scan_id != s.scan.scan_id) {  // a new scan: a new cloud
        s.xyz.clear();
        s.stripes = 0;
        s.have_cloud = false;
      }
      s.have_scan = true;
      s.scan = m;
    });
    server.subscribe<stripe_points_t>(stripe::channels::kPoints, [&](const stripe_points_t& m) {
      if (!s.have_scan || m.scan_id != s.scan.scan_id || m.scan_id == 0) return;
      const auto n = static_cast<size_t>(std::max(0, m.num_points));
      if (m.x_mm.size() != n || m.y_mm.size() != n || m.z_mm.size() != n) return;
      for (size_t i = 0; i < n; ++i) {
        if (!std::isfinite(m.x_mm[i]) || !std::isfinite(m.y_mm[i]) || !std::isfinite(m.z_mm[i]))
          continue;
        s.xyz.push_back(m.x_mm[i]);
        s.xyz.push_back(m.y_mm[i]);
        s.xyz.push_back(m.z_mm[i]);
      }
      ++s.stripes;
    });
    server.subscribe<stripe_cloud_t>(stripe::channels::kCloud, [&](const stripe_cloud_t& m) {
      if (!s.have_scan || m.scan_id != s.scan.scan_id) return;
      s.have_cloud = true;
      s.cloud = m;
    });
    server.set_state_builder([&](int64_t) {
      nlohmann::json j;
      if (s.have_scan) {
        const stripe_scan_t& m = s.scan;
        j["scan"] = {{"scan_id", m.scan_id},
                     {"state", state_name(m.state)},
                     {"reason", m.reason},
                     {"region_mm", m.region_mm},
                     {"step_mm", m.step_mm},
                     {"height_mm", m.height_mm},
                     {"stripes_planned", m.stripes_planned},
                     {"stripes_captured", m.stripes_captured},
                     {"stripes_skipped", m.stripes_skipped},
                     {"elapsed_s", m.elapsed_s},
                     {"stripes_per_s", m.stripes_per_s}};
      } else {
        j["scan"] = nullptr;
      }
      j["cloud"] = {{"points", s.xyz.size() / 3},
                    {"stripes", s.stripes},
                    {"complete", s.have_cloud},
                    {"path", s.have_cloud ? s.cloud.path : ""}};
      return j;
    });
    server.add_json_route("/api/cloud", [&](int64_t) {
      // Points to 0.1 mm: a third of the text, finer than the view shows.
      nlohmann::json xyz = nlohmann::json::array();
      for (float v : s.xyz) xyz.push_back(std::round(static_cast<double>(v) * 10.0) / 10.0);
      return nlohmann::json{{"scan_id", s.have_scan ? s.scan.scan_id : 0},
                            {"points", s.xyz.size() / 3},
                            {"xyz", std::move(xyz)}};
    });
    server.run("stripe display");
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
  return 0;
}
