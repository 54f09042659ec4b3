// ephor-catch-worldmodel: NASREM's Level 2 world model of the ball (paper
// 000, section 5.4). Turns each of ephor-catch-vision's centroids into a 3-D
// ball position (the ray through the centroid meets the board plane raised
// by the ball's radius), applies the paper's two filters (off the board;
// jumps the incline does not allow), filters position and velocity in the
// board plane (Kalman) and predicts where and when the ball leaves the
// bottom edge and crosses the catch plane, for every frame.
//
//   subscribes  CATCH_BALL (catch_ball_t), CATCH_BOARD_POSE (catch_board_pose_t,
//               the camera's pose), CATCH_SURVEY (catch_survey_t, the board in W)
//   publishes   CATCH_WORLD (catch_world_t), one per CATCH_BALL once both
//               poses are known
//   tasks       model (triggered by CATCH_BALL: always the newest one; with
//               --every-ball every one in order, for replays that must give
//               the live run's outputs again)

#include <atomic>
#include <cmath>
#include <iostream>
#include <limits>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include "common/catch/board_file.h"
#include "common/catch/board_survey.h"
#include "common/catch/camera_file.h"
#include "common/catch/catch_channels.h"
#include "common/catch/worldmodel/ball_world_model.h"
#include "common/config/repo_paths.h"
#include "common/config/text_proto.h"
#include "common/lcm/bus.h"
#include "common/lcm/inbox.h"
#include "common/lcm/mailbox.h"
#include "common/log/log.h"
#include "common/runtime/process_args.h"
#include "common/runtime/task_runtime.h"
#include "common/time/clock.h"
#include "ephor/catch_ball_t.hpp"
#include "ephor/catch_board_pose_t.hpp"
#include "ephor/catch_pegs_t.hpp"
#include "ephor/catch_survey_t.hpp"
#include "ephor/catch_world_t.hpp"
#include "procs/catch/worldmodel/world_message.h"

using namespace ephor;
using namespace ephor::catching;

int main(int argc, char** argv) {
  block_shutdown_signals();
  CLI::App app{
      "ephor-catch-worldmodel: the ball on the board in 3-D, filtered, its exit predicted"};
  ProcessArgs args;
  add_process_flags(app, args, "worldmodel");
  std::string board_path = "deploy/catch/board.pbtxt", camera_path = "deploy/catch/camera.pbtxt";
  double duration_s = 0.0;
  bool no_pegs = false;
  int spread_samples = 0;
  bool every_ball = false;
  app.add_option("--board", board_path, "board file (common/catch/board.proto)");
  app.add_flag("--no-pegs", no_pegs,
               "predict the exit as if the board had no pegs (ignore CATCH_PEGS)");
  app.add_option("--camera", camera_path, "camera file (common/catch/camera.proto)");
  app.add_option("--spread-samples", spread_samples,
                 "publish as the exit and catch point the cover of the prediction's spread: "
                 "this many states drawn from the filter's covariance (and pegs from their "
                 "survey error) rolled past the pegs, the point within the cup's capture radius "
                 "of the most (ExitSpread); 0 = the mean's prediction")
      ->check(CLI::Range(0, 1000));
  app.add_flag("--every-ball", every_ball,
               "take every CATCH_BALL in order instead of the newest (a replay: a measurement "
               "skipped on a busy machine changes the filter's later states)");
  app.add_option("--duration", duration_s, "exit after this many seconds (0 = until signalled)");
  if (const auto exit_status = ephor::parse_flags(app, argc, argv)) return *exit_status;
  init_logging(args.name);

  try {
    const BoardSpec board = load_board_file(resolve_repo_path(board_path));
    const CameraIntrinsics intrinsics = load_camera_file(resolve_repo_path(camera_path));
    Bus bus(args.lcm_url, args.name);
    TaskRuntime runtime(bus, {args.name, args.host, !args.no_mlock});

    std::mutex mutex;
    std::optional<Pose> board_to_camera;
    std::optional<BoardPlacement> placement;
    std::optional<BallWorldModel> model;
    Mailbox<catch_ball_t> balls;
    Inbox<catch_ball_t> every(4096);  // --every-ball: 68 s of frames at 60 Hz
    std::atomic<int64_t> bad_messages{0}, published{0};

    bus.subscribe<catch_board_pose_t>(
        catching::channels::kBoardPose, [&](const catch_board_pose_t& m) {
          if (!m.valid) return;
          Pose pose = Pose::Identity();
          for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) pose.linear()(i, j) = m.r[3 * i + j];
            pose.translation()[i] = m.t_mm[i];
          }
          if (!pose.matrix().allFinite() || std::abs(pose.linear().determinant() - 1.0) > 1e-3) {
            ++bad_messages;
            spdlog::warn("CATCH_BOARD_POSE ignored: not a finite rotation");
            return;
          }
          std::lock_guard<std::mutex> lock(mutex);
          if (!board_to_camera)
            spdlog::info(
                "camera pose from the circles: board origin at ({:.1f}, {:.1f}, {:.1f}) mm in the "
                "camera frame",
                m.t_mm[0], m.t_mm[1], m.t_mm[2]);
          board_to_camera = pose;
        });
    bus.subscribe<catch_survey_t>(catching::channels::kSurvey, [&](const catch_survey_t& m) {
      std::string why;
      const auto fitted = placement_from_survey(board, m.board_mm, m.world_mm, why);
      if (!fitted) {
        ++bad_messages;
        spdlog::warn("CATCH_SURVEY ignored: {}", why);
        return;
      }
      std::lock_guard<std::mutex> lock(mutex);
      if (!placement)
        spdlog::info("board in the work cell from the survey: incline {:.2f} deg",
                     fitted->incline_rad * 180.0 / M_PI);
      placement = fitted;
    });
    // The pegs, once (the board does not change while we run).
    std::optional<std::pair<std::vector<Eigen::Vector2d>, double>> pegs;
    bool pegs_applied = false;
    bus.subscribe<catch_pegs_t>(catching::channels::kPegs, [&](const catch_pegs_t& m) {
      std::vector<Eigen::Vector2d> centres;
      for (int i = 0; i < m.num_pegs; ++i) centres.emplace_back(m.x_mm[i], m.y_mm[i]);
      bool finite = std::isfinite(m.peg_diameter_mm) && m.peg_diameter_mm > 0.0;
      for (const auto& c : centres) finite = finite && c.allFinite();
      if (!finite) {
        ++bad_messages;
        spdlog::warn("CATCH_PEGS ignored: a peg or the diameter is not finite and positive");
        return;
      }
      std::lock_guard<std::mutex> lock(mutex);
      if (!pegs) spdlog::info("{} pegs: the exit prediction rolls the ball past them", m.num_pegs);
      if (!pegs) pegs.emplace(std::move(centres), 0.5 * m.peg_diameter_mm);
    });
    bus.subscribe<catch_ball_t>(catching::channels::kBall, [&](const catch_ball_t& m) {
      if (every_ball)
        every.push(m);
      else
        balls.put(m);
      runtime.trigger("model");
    });

    const auto model_one = [&](const catch_ball_t* ball) {
      if (!model) {
        if (!board_to_camera || !placement) return;  // not initialised yet
        BallWorldModelParams params;
        params.acquire_max_y_mm = 150.0;  // balls are released 30 mm from the top
        params.spread.samples = spread_samples;
        model.emplace(board, *placement, intrinsics, *board_to_camera, params);
        spdlog::info("initialised: tracking");
      }
      if (pegs && !pegs_applied && !no_pegs) {
        model->set_pegs(pegs->first, pegs->second);
        pegs_applied = true;
      }
      bool bad = false;
      const std::optional<Eigen::Vector2d> centroid = centroid_of(*ball, &bad);
      if (bad) ++bad_messages;
      const BallFrame& f = model->update(ball->utime, centroid);
      catch_world_t out = world_message_of(f, *ball);
      out.latency_ms = static_cast<float>(static_cast<double>(wall_us() - ball->utime) / 1e3);
      bus.publish(catching::channels::kWorld, out);
      ++published;
    };
    runtime.add_triggered("model", std::chrono::milliseconds(8), [&] {
      std::vector<catch_ball_t> todo;
      if (every_ball) {
        todo = every.drain();
      } else if (auto newest = balls.take()) {
        todo.push_back(std::move(*newest));
      }
      std::lock_guard<std::mutex> lock(mutex);
      for (const catch_ball_t& ball : todo) model_one(&ball);
    });

    runtime.start();
    spdlog::info(
        "ready: waiting for the camera pose (CATCH_BOARD_POSE) and the board survey "
        "(CATCH_SURVEY)");
    wait_for_shutdown_signal(duration_s);
    runtime.stop();
    std::lock_guard<std::mutex> lock(mutex);
    spdlog::info("summary: {} outputs, {} exits, {} lost, {} bad messages", published.load(),
                 model ? model->exits() : 0, model ? model->lost() : 0, bad_messages.load());
  } catch (const ephor::ConfigError& e) {
    // A file given on the command line is bad: one line, status 2 (issue 18).
    std::cerr << "ephor-catch-worldmodel: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
  return 0;
}
