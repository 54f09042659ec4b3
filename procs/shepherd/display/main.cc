// ephor-display: the shepherding system's live web page for watching and
// steering it (paper 003 section 3.2, the display process). The generic
// part (HTTP, embedded page, /api/frame.jpg, /api/debug, /api/rates, the
// task table, STOP) is DisplayServer's; here: the shepherding messages into
// DisplayState (the page's JSON) and the page's controls (CommandValidator)
// out as full-state commands.
//
//   ephor-display [--http-address 127.0.0.1] [--http-port 8080] [--calibration FILE]
//                 [--sim-seed N] [--max-fps 15]

#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include "common/calibration/field_calibration.h"
#include "common/config/text_proto.h"
#include "common/display/display_server.h"
#include "common/display/web_assets.h"
#include "common/geometry/workcell.h"
#include "common/lcm/bus.h"
#include "common/lcm/channels.h"
#include "common/log/log.h"
#include "common/runtime/process_args.h"
#include "common/time/clock.h"
#include "procs/shepherd/display/command_validator.h"
#include "procs/shepherd/display/display_state.h"
#include "procs/shepherd/display/shepherd_display_feed.h"
#include "procs/shepherd/display/shepherd_lcm_json.h"

namespace {

using namespace ephor;
using ephor::display::Controls;

std::filesystem::path repo_dir() {
  if (const char* env = std::getenv("EPHOR_SOURCE_DIR"); env != nullptr && *env != '\0') return env;
  std::error_code ec;
  const auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec) return ".";
  return exe.parent_path().parent_path().parent_path();
}

// Every message the page hears goes to the feed, under DisplayServer's lock.
void subscribe_all(display::DisplayServer& server, display::ShepherdDisplayFeed& feed) {
  server.set_frame_hook([&](const camera_frame_t& m, int64_t now_us) { feed.on_frame(m, now_us); });
  server.subscribe<shepherd_blobs_t>(
      channels::kBlobs, [&](const shepherd_blobs_t& m) { feed.on_blobs(m, wall_us()); });
  server.subscribe<shepherd_vision_cmd_t>(
      channels::kVisionCmd, [&](const shepherd_vision_cmd_t& m) { feed.on_vision_cmd(m); });
  server.subscribe<shepherd_objects_t>(
      channels::kObjects, [&](const shepherd_objects_t& m) { feed.on_objects(m, wall_us()); });
  server.subscribe<shepherd_planner_status_t>(
      channels::kPlannerStatus,
      [&](const shepherd_planner_status_t& m) { feed.on_planner_status(m, wall_us()); });
  server.subscribe<shepherd_planner_cmd_t>(
      channels::kPlannerCmd, [&](const shepherd_planner_cmd_t& m) { feed.on_planner_cmd(m); });
  server.subscribe<arm_state_t>(channels::kArmState,
                                [&](const arm_state_t& m) { feed.on_arm_state(m, wall_us()); });
  server.subscribe<shepherd_ground_truth_t>(
      channels::kGroundTruth,
      [&](const shepherd_ground_truth_t& m) { feed.on_truth(m, wall_us()); });
  server.subscribe<shepherd_sim_cmd_t>(channels::kSimCmd,
                                       [&](const shepherd_sim_cmd_t& m) { feed.on_sim_cmd(m); });
  server.subscribe<arm_cmd_t>(channels::kArmCmd, [&](const arm_cmd_t& m) { feed.on_arm_cmd(m); });
  // Heard for the debug dump and the rates only.
  server.subscribe<arm_goal_t>(channels::kArmGoal, nullptr);
  server.subscribe<arm_ack_t>(channels::kArmAck, nullptr);
  server.subscribe<motion_done_t>(channels::kMotionDone, nullptr);
  server.subscribe<shepherd_display_box_t>(channels::kDisplayBox, nullptr);
}

// Publishes the part of `c` that `target` names. Returns false on a send failure.
bool publish_control(Bus& bus, display::Target target, const Controls& c) {
  switch (target) {
    case display::Target::kVision: {
      shepherd_vision_cmd_t m{};
      m.utime = wall_us();
      m.paused = c.vision.paused;
      m.mode = static_cast<int8_t>(c.vision.mode);
      m.scan = static_cast<int8_t>(c.vision.scan);
      m.threshold = c.vision.threshold;
      return bus.publish(channels::kVisionCmd, m);
    }
    case display::Target::kSim: {
      shepherd_sim_cmd_t m{};
      m.utime = wall_us();
      m.sheep = c.sim.sheep;
      m.reset = false;
      m.seed = c.sim.seed;
      return bus.publish(channels::kSimCmd, m);
    }
    case display::Target::kPlanner: {
      shepherd_planner_cmd_t m{};
      m.utime = wall_us();
      m.planner = c.planner;
      return bus.publish(channels::kPlannerCmd, m);
    }
    case display::Target::kBox: {
      shepherd_display_box_t m{};
      m.utime = wall_us();
      m.visible = c.box.visible;
      m.u = static_cast<float>(c.box.u);
      m.v = static_cast<float>(c.box.v);
      m.half_size_px = static_cast<float>(c.box.half_size_px);
      return bus.publish(channels::kDisplayBox, m);
    }
    case display::Target::kNone:
      break;
  }
  return false;
}

}  // namespace

int main(int argc, char** argv) {
  block_shutdown_signals();
  CLI::App app{"ephor-display: live web page for watching and steering the system"};
  ProcessArgs args;
  add_process_flags(app, args, "display");
  display::DisplayServerOptions server_options;
  server_options.http_port = 8080;
  server_options.camera_channel = channels::kCamera;
  server_options.estop = true;
  std::string calibration_path;
  display::DisplayOptions options;
  app.add_option("--http-address", server_options.http_address,
                 "address to serve the page on (default loopback)");
  app.add_option("--http-port", server_options.http_port, "TCP port of the page (default 8080)")
      ->check(CLI::Range(1, 65535));
  app.add_option("--calibration", calibration_path,
                 "image-to-field calibration (Protobuf text); default "
                 "deploy/calibration/sim.pbtxt in the repository");
  app.add_option("--max-fps", server_options.max_fps,
                 "camera images per second at most (default 15)")
      ->check(CLI::Range(1, 30));
  app.add_option("--path-horizon-s", options.path_horizon_s,
                 "predicted paths: velocity x this, s (default 3)")
      ->check(CLI::Range(0.0, 30.0));
  app.add_option("--tool-radius-mm", options.tool_radius_mm,
                 "footprint of the manipulator tip drawn on the table, mm (default 40)")
      ->check(CLI::Range(1.0, 500.0));
  int sim_seed = 1;
  app.add_option(
      "--sim-seed", sim_seed,
      "the simulator's seed, sent back unchanged in shepherd_sim_cmd_t (full state) until a "
      "SIM_CMD names another (default 1, ephor-sim's default)");
  if (const auto exit_status = ephor::parse_flags(app, argc, argv)) return *exit_status;
  init_logging(args.name);

  try {
    if (calibration_path.empty()) {
      calibration_path = (repo_dir() / "deploy" / "calibration" / "sim.pbtxt").string();
    }
    const auto calibration = calibration::FieldCalibration::load(calibration_path);
    const geometry::Workcell workcell;
    display::OverlayGeometry geometry(calibration.matrix_at_height(0.0), workcell.field_length_mm,
                                      workcell.field_width_mm);

    Bus bus(args.lcm_url, args.name);
    display::ShepherdDisplayFeed feed(geometry, options, sim_seed);
    display::DisplayServer server(bus, server_options, &display::find_web_asset);
    subscribe_all(server, feed);
    server.set_state_builder([&](int64_t now_us) { return feed.state(now_us); });
    server.set_command_handler(
        [&](const std::string& command, const std::map<std::string, std::string>& params) {
          const display::CommandValidator validator(feed.frame_width(), feed.frame_height());
          const auto r = validator.validate(command, params, feed.controls());
          if (!r.ok) return display::CommandReply::refused(r.reason);
          if (!publish_control(bus, r.target, r.controls)) {
            return display::CommandReply::refused("could not publish the command on LCM", 500);
          }
          feed.set_controls(r.controls);
          return display::CommandReply::sent();
        });
    spdlog::info("calibration {}", calibration_path);
    server.run("display");
  } catch (const ephor::ConfigError& e) {
    // A file given on the command line is bad: one line, status 2 (issue 18).
    std::cerr << "ephor-display: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
  return 0;
}
