// ephor-catch-sim: the simulated ball-catching cell in real time (paper 000):
// the pegged board and its rolling ball (BoardWorld), the camera at its
// per-seed pose (BoardRenderer, 60 Hz), and the PUMA 560's servo layer
// (ArmServo) holding the cup. Balls are released one after another; each is
// judged caught or missed from geometry when it crosses the catch plane.
//
//   ephor-catch-sim --seed 1 --balls 10
//
// Tasks (scheduled by ephor-scheduler through the TaskRuntime):
//   physics  every 2 ms: advances board and servo to the monotonic clock in
//            1 ms steps, publishes ARM_SERVO (joint_state_t) every 4 ms
//   camera   every 1/fps: renders CAMERA (camera_frame_t) and CATCH_TRUTH
//            (catch_truth_t, same utime and frame_index)
// Publishes CATCH_PEGS with the survey: the pegs' centres with 0.5 mm noise.
// Subscribes ARM_TRAJECTORY (joint_trajectory_t; malformed ones are logged,
// counted and ignored). Publishes CATCH_SURVEY every second: the three board
// points the arm's tool touched (see below).
//
// With --balls N > 0 the process exits with status 0 one second after the
// N-th ball is judged (the manifest's ends_run stops the run then).
//
// Not simulated: the calibration command that drives the arm to touch three
// points of the board (paper 000, section 3). The simulator publishes the
// three touched points as that procedure would measure them: the true board
// points in W with 0.5 mm of Gaussian measurement noise per axis.
//
// Time: simulated time runs with CLOCK_MONOTONIC from start-up; a message's
// utime is the wall clock at start plus the simulated time of its state.

#include <atomic>
#include <cmath>
#include <iostream>
#include <mutex>
#include <optional>
#include <random>
#include <string>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "common/arm/arm_servo.h"
#include "common/arm/arm_workcell.h"
#include "common/arm/servo_messages.h"
#include "common/catch/board_file.h"
#include "common/catch/board_model.h"
#include "common/catch/catch_channels.h"
#include "common/catch/sim/ball_sequence.h"
#include "common/catch/sim/board_renderer.h"
#include "common/catch/sim/board_world.h"
#include "common/catch/sim/catch_cell.h"
#include "common/catch/sim/catch_scenario.h"
#include "common/config/repo_paths.h"
#include "common/config/text_proto.h"
#include "common/geometry/workcell_file.h"
#include "common/lcm/bus.h"
#include "common/lcm/channels.h"
#include "common/log/log.h"
#include "common/motion/motion_planner.h"
#include "common/runtime/process_args.h"
#include "common/runtime/task_runtime.h"
#include "common/time/clock.h"
#include "ephor/camera_frame_t.hpp"
#include "ephor/catch_pegs_t.hpp"
#include "ephor/catch_survey_t.hpp"
#include "ephor/catch_truth_t.hpp"
#include "ephor/joint_state_t.hpp"
#include "ephor/joint_trajectory_t.hpp"
#include "procs/catch/sim/sim_messages.h"

using namespace ephor;
using namespace ephor::catching;

int main(int argc, char** argv) {
  block_shutdown_signals();
  CLI::App app{"ephor-catch-sim: simulated pegged board, rolling ball, camera and PUMA 560 servo"};
  ProcessArgs args;
  add_process_flags(app, args, "sim");
  uint64_t seed = 1;
  int balls = 0;
  double fps = 60.0, gap_s = 1.0, first_release_s = 6.0, duration_s = 0.0;
  std::string workcell_path = "deploy/catch/workcell.pbtxt",
              board_path = "deploy/catch/board.pbtxt", png_path;
  app.add_option("--seed", seed, "random seed: incline, pegs, camera pose, releases (default 1)");
  app.add_option("--balls", balls, "balls to release, then exit 0 (0 = until stopped)")
      ->check(CLI::Range(0, 1000000));
  app.add_option("--fps", fps, "camera frames per second (default 60, the PIPE's field rate)")
      ->check(CLI::Range(1.0, 240.0));
  app.add_option("--gap-s", gap_s, "time between one ball's judgement and the next release, s")
      ->check(CLI::Range(0.2, 60.0));
  app.add_option("--first-release-s", first_release_s,
                 "when the first ball is released, s after start-up (vision finds the board, the "
                 "arm comes from its park pose to the ready point; default 6)")
      ->check(CLI::Range(0.0, 600.0));
  app.add_option("--workcell", workcell_path, "work cell file (common/geometry/workcell.proto)");
  app.add_option("--board", board_path, "board file (common/catch/board.proto)");
  app.add_option("--duration", duration_s, "exit after this many seconds (0 = until signalled)");
  app.add_option("--write-png", png_path,
                 "render the first frame with a ball to this PNG and exit");
  if (const auto exit_status = ephor::parse_flags(app, argc, argv)) return *exit_status;
  init_logging(args.name);

  try {
    const BoardSpec board = load_board_file(resolve_repo_path(board_path));
    const geometry::Workcell cell = geometry::load_workcell_file(resolve_repo_path(workcell_path));
    CatchSimProcess p(CatchScenario::draw(seed, board), cell, balls, gap_s, first_release_s);
    BoardRenderer renderer(p.scenario, CupSpec{}, seed);
    cv::Mat image;

    if (!png_path.empty()) {
      const BallRelease r = p.scenario.release(0);
      renderer.render(Eigen::Vector3d(r.x_mm, r.y_mm + 300.0, board.ball_radius_mm()),
                      p.catch_cell.arm_view(p.servo.state().q), image);
      cv::imwrite(png_path, image);
      spdlog::info("wrote {}", png_path);
      return 0;
    }

    camera_frame_t frame;
    frame.width = renderer.width();
    frame.height = renderer.height();
    Bus bus(args.lcm_url, args.name);
    TaskRuntime runtime(bus, {args.name, args.host, !args.no_mlock});

    bus.subscribe<joint_trajectory_t>(ephor::channels::kArmTrajectory,
                                      [&p](const joint_trajectory_t& m) { p.on_trajectory(m); });

    p.wall0_us = wall_us();
    p.mono0_ns = mono_ns();
    auto advance_to_now = [&p] {
      p.advance_to(static_cast<double>(mono_ns() - p.mono0_ns) * 1e-9);
    };

    runtime.add_periodic("physics", std::chrono::milliseconds(2), [&] {
      joint_state_t m;
      {
        std::lock_guard<std::mutex> lock(p.mutex);
        advance_to_now();
        if (++p.servo_ticks % 2 != 0) return;  // ARM_SERVO at 250 Hz
        m = p.servo_message();
      }
      bus.publish(ephor::channels::kArmServo, m);
    });

    // The touched points: three board points, measured with 0.5 mm noise.
    catch_survey_t survey{};
    {
      const CatchScenario::TouchedPoints touched = p.scenario.touched_points();
      for (int i = 0; i < 3; ++i) {
        for (int k = 0; k < 2; ++k) survey.board_mm[i][k] = touched.board_mm[i][k];
        for (int k = 0; k < 3; ++k) survey.world_mm[i][k] = touched.world_mm[i][k];
      }
    }

    // The pegs as measured once when the board was set up: true centres with
    // 0.5 mm of noise (as the survey's touches), published with the survey.
    catch_pegs_t pegs_msg{};
    {
      pegs_msg.peg_diameter_mm = p.scenario.peg_diameter_mm;
      pegs_msg.num_pegs = static_cast<int32_t>(p.scenario.pegs.size());
      for (const Eigen::Vector2d& peg : p.scenario.measured_pegs()) {
        pegs_msg.x_mm.push_back(peg.x());
        pegs_msg.y_mm.push_back(peg.y());
      }
    }

    std::atomic<bool> finished{false};
    int logged_ball = -1;
    runtime.add_periodic("camera", std::chrono::nanoseconds(static_cast<int64_t>(1e9 / fps)), [&] {
      std::optional<Eigen::Vector3d> ball;
      ArmView arm;
      catch_truth_t truth{};
      {
        std::lock_guard<std::mutex> lock(p.mutex);
        advance_to_now();
        const BallState s = p.world.state();
        if (s.on_board) ball = s.position_b_mm;
        arm = p.catch_cell.arm_view(p.servo.state().q);
        truth = p.truth();
        if (p.balls.finished_for_s(p.world.time_s()) > 1.0) finished = true;
        if (const auto& last = p.balls.last(); last && last->ball != logged_ball) {
          logged_ball = last->ball;
          spdlog::info(
              "ball {}: {}; it fell through the cup's plane at ({:.0f}, {:.0f}, {:.0f}) "
              "mm, cup at ({:.0f}, {:.0f}, {:.0f}) mm{}",
              last->ball, last->reason, last->ball_w_mm.x(), last->ball_w_mm.y(),
              last->ball_w_mm.z(), last->cup_w_mm.x(), last->cup_w_mm.y(), last->cup_w_mm.z(),
              last->oracle_reachable ? "" : " (out of the arm's reach in the time it gave)");
        }
      }
      const auto ball_px = renderer.render(ball, arm, image);
      frame.utime = truth.utime;
      frame.frame_index = p.frames;
      frame.data.assign(image.data, image.data + image.total());
      frame.size = static_cast<int32_t>(frame.data.size());
      bus.publish(ephor::channels::kCamera, frame);
      truth.frame_index = frame.frame_index;
      if (ball_px) {
        truth.ball_px[0] = ball_px->x();
        truth.ball_px[1] = ball_px->y();
      }
      bus.publish(catching::channels::kTruth, truth);
      if (frame.frame_index % static_cast<int64_t>(fps) == 0) {
        survey.utime = wall_us();
        bus.publish(catching::channels::kSurvey, survey);
        pegs_msg.utime = survey.utime;
        bus.publish(catching::channels::kPegs, pegs_msg);
      }
      ++p.frames;
    });

    runtime.start();
    spdlog::info("running: seed {}, incline {:.1f} deg, {} pegs, {} balls, {} fps", seed,
                 p.scenario.placement.incline_rad * 180.0 / M_PI, p.scenario.pegs.size(),
                 balls == 0 ? std::string("endless") : std::to_string(balls), fps);
    const auto t_end =
        duration_s > 0 ? mono_ns() + static_cast<int64_t>(duration_s * 1e9) : INT64_MAX;
    while (!finished && mono_ns() < t_end) {
      if (wait_for_shutdown_signal(0.05) != 0) break;
    }
    runtime.stop();
    std::lock_guard<std::mutex> lock(p.mutex);
    spdlog::info(
        "summary: {} balls judged, {} caught, {} oracle-reachable, {} frames, {} "
        "trajectories ignored, {} physics skips",
        p.balls.done(), p.balls.caught(), p.balls.oracle_reachable(), p.frames.load(),
        p.trajectories_refused.load(), p.physics_skips.load());
  } catch (const ephor::ConfigError& e) {
    // A file given on the command line is bad: one line, status 2 (issue 18).
    std::cerr << "ephor-catch-sim: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
  return 0;
}
