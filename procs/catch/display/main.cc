// ephor-catch-display: the catching system's live web page (paper 000;
// issue 14): the camera image with the board's outline and circles (through
// the pose vision found), the ball, its window of interest, the predicted
// path and exit point, the catch point and the cup on the arm (once the
// survey placed the board in the work cell), and the catch count; the STOP
// button for the arm. DisplayServer serves it; the state is CatchDisplayState's.
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
#include "procs/catch/display/catch_display_state.h"
#include "procs/catch/display/catch_lcm_json.h"
#include "procs/catch/display/catch_web_assets.h"

namespace {

using namespace ephor;
using namespace ephor::catch_display;

template <size_t N, class T>
std::array<double, N> arr(const T (&v)[N]) {
  std::array<double, N> a{};
  for (size_t i = 0; i < N; ++i) a[i] = static_cast<double>(v[i]);
  return a;
}

void subscribe_all(display::DisplayServer& server, CatchDisplayState& state) {
  server.set_frame_hook([&](const camera_frame_t& m, int64_t now_us) {
    state.on_frame(m.frame_index, m.width, m.height, now_us);
  });
  server.subscribe<catch_board_pose_t>(catching::channels::kBoardPose,
                                       [&](const catch_board_pose_t& m) {
                                         BoardPoseView p;
                                         p.valid = m.valid;
                                         p.reason = m.reason;
                                         p.r = arr(m.r);
                                         p.t_mm = arr(m.t_mm);
                                         p.circles_px = arr(m.circles_px);
                                         p.reprojection_rms_px = m.reprojection_rms_px;
                                         state.on_board_pose(p, wall_us());
                                       });
  server.subscribe<catch_survey_t>(catching::channels::kSurvey, [&](const catch_survey_t& m) {
    SurveyView s;
    for (int i = 0; i < 3; ++i) {
      for (int k = 0; k < 2; ++k) s.board_mm[i][k] = m.board_mm[i][k];
      for (int k = 0; k < 3; ++k) s.world_mm[i][k] = m.world_mm[i][k];
    }
    state.on_survey(s, wall_us());
  });
  server.subscribe<catch_ball_t>(catching::channels::kBall, [&](const catch_ball_t& m) {
    BallView b;
    b.frame_index = m.frame_index;
    b.found = m.found;
    b.u = m.u;
    b.v = m.v;
    b.u_blob = m.u_blob;
    b.v_blob = m.v_blob;
    b.area_px = m.area_px;
    for (int i = 0; i < 4; ++i) b.window[static_cast<size_t>(i)] = m.window[i];
    b.exec_ms = m.exec_ms;
    state.on_ball(b, wall_us());
  });
  server.subscribe<catch_world_t>(catching::channels::kWorld, [&](const catch_world_t& m) {
    WorldView w;
    w.utime = m.utime;
    w.frame_index = m.frame_index;
    w.status = m.status;
    w.ball_id = m.ball_id;
    w.reason = m.reason;
    w.position_b_mm = arr(m.position_b_mm);
    w.velocity_b_mm_s = arr(m.velocity_b_mm_s);
    w.has_prediction = m.has_prediction;
    w.exit_x_b_mm = m.exit_x_b_mm;
    w.exit_sigma_mm = m.exit_sigma_mm;
    w.exit_utime = m.exit_utime;
    w.exit_sigma_s = m.exit_sigma_s;
    w.catch_point_w_mm = arr(m.catch_point_w_mm);
    w.catch_utime = m.catch_utime;
    w.latency_ms = m.latency_ms;
    state.on_world(w, wall_us());
  });
  server.subscribe<catch_truth_t>(catching::channels::kTruth, [&](const catch_truth_t& m) {
    TruthView t;
    t.ball = m.ball;
    t.phase = m.phase;
    t.ball_px = arr(m.ball_px);
    t.incline_deg = m.incline_deg;
    t.balls_done = m.balls_done;
    t.caught = m.caught;
    t.oracle_reachable = m.oracle_reachable;
    t.last_ball = m.last_ball;
    t.last_caught = m.last_caught;
    t.last_oracle_reachable = m.last_oracle_reachable;
    t.last_reason = m.last_reason;
    state.on_truth(t, wall_us());
  });
  server.subscribe<arm_state_t>(channels::kArmState, [&](const arm_state_t& m) {
    state.on_arm({m.x_mm, m.y_mm, m.z_mm, m.moving != 0, m.speed_mm_s}, wall_us());
  });
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
    CatchDisplayState state(board, camera);
    display::DisplayServer server(bus, server_options, &find_web_asset);
    subscribe_all(server, state);
    server.set_state_builder([&](int64_t now_us) { return state.to_json(now_us); });
    server.run("catch display");
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
  return 0;
}
