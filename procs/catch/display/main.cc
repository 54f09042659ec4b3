// ephor-catch-display: the catching system's live web page (paper 000;
// issue 14): the camera image with the board's outline and circles (through
// the pose vision found), the ball, its window of interest, the predicted
// path and exit point, the catch point and the cup on the arm (once the
// survey placed the board in the work cell), and the catch count; the STOP
// button for the arm. DisplayServer serves it; CatchDisplayFeed converts the messages
// for CatchDisplayState and builds the state.
//
//   ephor-catch-display [--http-address 127.0.0.1] [--http-port 8081]
//                       [--board deploy/catch/board.pbtxt] [--camera deploy/catch/camera.pbtxt]
//
//   subscribes  CAMERA, CATCH_BOARD_POSE, CATCH_SURVEY, CATCH_BALL, CATCH_WORLD,
//               CATCH_TRUTH, ARM_STATE, ARM_GOAL, EPHOR_SCHED_STATUS
//   publishes   ESTOP (estop_t) when the page's STOP or release is pressed

#include <string>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include "common/catch/board_file.h"
#include "common/catch/camera_file.h"
#include "common/catch/catch_channels.h"
#include "common/config/repo_paths.h"
#include "common/display/display_server.h"
#include "common/lcm/bus.h"
#include "common/lcm/channels.h"
#include "common/log/log.h"
#include "common/runtime/process_args.h"
#include "common/time/clock.h"
#include "procs/catch/display/catch_display_feed.h"
#include "procs/catch/display/catch_lcm_json.h"
#include "procs/catch/display/catch_web_assets.h"

namespace {

using namespace ephor;
using namespace ephor::catch_display;

void subscribe_all(display::DisplayServer& server, CatchDisplayFeed& feed) {
  server.set_frame_hook([&](const camera_frame_t& m, int64_t now_us) { feed.on_frame(m, now_us); });
  server.subscribe<catch_board_pose_t>(
      catching::channels::kBoardPose,
      [&](const catch_board_pose_t& m) { feed.on_board_pose(m, wall_us()); });
  server.subscribe<catch_survey_t>(catching::channels::kSurvey,
                                   [&](const catch_survey_t& m) { feed.on_survey(m, wall_us()); });
  server.subscribe<catch_ball_t>(catching::channels::kBall,
                                 [&](const catch_ball_t& m) { feed.on_ball(m, wall_us()); });
  server.subscribe<catch_world_t>(catching::channels::kWorld,
                                  [&](const catch_world_t& m) { feed.on_world(m, wall_us()); });
  server.subscribe<catch_truth_t>(catching::channels::kTruth,
                                  [&](const catch_truth_t& m) { feed.on_truth(m, wall_us()); });
  server.subscribe<arm_state_t>(channels::kArmState,
                                [&](const arm_state_t& m) { feed.on_arm_state(m, wall_us()); });
  // Heard for the debug dump and the rates only.
  server.subscribe<arm_goal_t>(channels::kArmGoal, nullptr);
}

}  // namespace

int main(int argc, char** argv) {
  block_shutdown_signals();
  CLI::App app{"ephor-catch-display: live web page of the ball catching system"};
  ProcessArgs args;
  add_process_flags(app, args, "display");
  display::DisplayServerOptions server_options;
  server_options.http_port = 8081;
  server_options.camera_channel = channels::kCamera;
  server_options.estop = true;
  std::string board_path = "deploy/catch/board.pbtxt", camera_path = "deploy/catch/camera.pbtxt";
  app.add_option("--http-address", server_options.http_address,
                 "address to serve the page on (default loopback)");
  app.add_option("--http-port", server_options.http_port, "TCP port of the page (default 8081)")
      ->check(CLI::Range(1, 65535));
  app.add_option("--max-fps", server_options.max_fps,
                 "camera images per second at most (default 15)")
      ->check(CLI::Range(1, 30));
  app.add_option("--board", board_path, "board file (common/catch/board.proto)");
  app.add_option("--camera", camera_path, "camera file (common/catch/camera.proto)");
  if (const auto exit_status = ephor::parse_flags(app, argc, argv)) return *exit_status;
  init_logging(args.name);

  try {
    const auto board = catching::load_board_file(resolve_repo_path(board_path));
    const auto camera = catching::load_camera_file(resolve_repo_path(camera_path));
    Bus bus(args.lcm_url, args.name);
    CatchDisplayFeed feed(board, camera);
    display::DisplayServer server(bus, server_options, &find_web_asset);
    subscribe_all(server, feed);
    server.set_state_builder([&](int64_t now_us) { return feed.state(now_us); });
    server.run("catch display");
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
  return 0;
}
