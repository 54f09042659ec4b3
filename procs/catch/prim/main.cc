// ephor-catch-prim: NASREM's manipulator Primitive level for catching
// (paper 000): from the world model's newest prediction of where and when
// the ball crosses the catch plane, streams cup goals (arm_goal_t KIND_POSE,
// tool down) that bring the cup there before the ball, refined as the
// prediction sharpens (CatchPlanner); the shared comm and arm processes
// carry them out.
//
//   subscribes  CATCH_WORLD (catch_world_t), ARM_STATE (arm_state_t: where the
//               cup is), CATCH_SURVEY (catch_survey_t: the board in W),
//               CATCH_BOARD_POSE (catch_board_pose_t: the arm stays parked, out
//               of the camera's way, until vision has found the board)
//   publishes   ARM_GOAL (arm_goal_t, KIND_POSE)
//   tasks       plan (triggered by CATCH_WORLD: always the newest one)

#include <algorithm>
#include <atomic>
#include <cmath>
#include <iostream>
#include <mutex>
#include <optional>
#include <string>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include "common/catch/board_file.h"
#include "common/catch/board_survey.h"
#include "common/catch/catch_channels.h"
#include "common/catch/prim/catch_planner.h"
#include "common/config/repo_paths.h"
#include "common/config/text_proto.h"
#include "common/lcm/bus.h"
#include "common/lcm/channels.h"
#include "common/lcm/mailbox.h"
#include "common/log/log.h"
#include "common/runtime/process_args.h"
#include "common/runtime/task_runtime.h"
#include "common/time/clock.h"
#include "ephor/arm_goal_t.hpp"
#include "ephor/arm_state_t.hpp"
#include "ephor/catch_board_pose_t.hpp"
#include "ephor/catch_survey_t.hpp"
#include "ephor/catch_world_t.hpp"
#include "procs/catch/prim/prim_messages.h"

int main(int argc, char** argv) {
  using namespace ephor;
  using namespace ephor::catching;
  block_shutdown_signals();
  CLI::App app{"ephor-catch-prim: streams cup goals to the predicted catch point"};
  ProcessArgs args;
  add_process_flags(app, args, "prim");
  std::string board_path = "deploy/catch/board.pbtxt";
  double duration_s = 0.0;
  PrimTuning tuning;  // the defaults: see PrimTuning
  double &commit_ahead_s = tuning.commit_ahead_s, &reaim_ms = tuning.reaim_ms,
         &hold_ms = tuning.hold_ms, &resend_mm = tuning.resend_mm, &freeze_ms = tuning.freeze_ms;
  app.add_option("--board", board_path, "board file (common/catch/board.proto)");
  app.add_option("--commit-ahead-s", commit_ahead_s,
                 "chase a predicted catch only when it is at most this far ahead, s (the cup "
                 "waits at the ready point before; default 10: committing late decides when)")
      ->check(CLI::Range(0.05, 10.0));
  app.add_option(
         "--reaim-ms", reaim_ms,
         "at most one new goal per this many ms (each makes the arm plan anew; default 250)")
      ->check(CLI::Range(10.0, 10000.0));
  app.add_option("--resend-mm", resend_mm,
                 "re-aim when the predicted catch point moved by more than this (or half its "
                 "sigma), mm (default 15)")
      ->check(CLI::Range(0.0, 1000.0));
  app.add_option("--freeze-ms", freeze_ms,
                 "no re-aim within this many ms of the predicted catch (the arm cannot use the "
                 "time; default 150)")
      ->check(CLI::Range(0.0, 10000.0));
  app.add_option("--hold-ms", hold_ms,
                 "after a ball, hold the cup this many ms past the predicted catch before going "
                 "back to the ready point (default 150)")
      ->check(CLI::Range(0.0, 10000.0));
  app.add_option(
         "--move-s-per-sqrt-mm", tuning.move_s_per_sqrt_mm,
         "commit late: the arm moves the cup d mm in this times sqrt(d) s (0.089 for the "
         "PUMA in the catching cell, the default); the first goal for a ball waits until the "
         "catch is no further ahead than that plus --commit-margin-s, and a re-aim goes "
         "only while it fits (0: chase at once)")
      ->check(CLI::Range(0.0, 10.0));
  app.add_option("--commit-margin-s", tuning.commit_margin_s,
                 "commit late: margin over the modelled move time, s (default 0.1)")
      ->check(CLI::Range(0.0, 10.0));
  app.add_option("--max-sigma-mm", tuning.max_sigma_mm,
                 "a prediction whose exit sigma is larger is not chased, mm (default 100)")
      ->check(CLI::Range(0.0, 100000.0));
  app.add_option("--duration", duration_s, "exit after this many seconds (0 = until signalled)");
  if (const auto exit_status = ephor::parse_flags(app, argc, argv)) return *exit_status;
  init_logging(args.name);

  try {
    const BoardSpec board = load_board_file(resolve_repo_path(board_path));
    Bus bus(args.lcm_url, args.name);
    TaskRuntime runtime(bus, {args.name, args.host, !args.no_mlock});
    std::mutex mutex;
    std::optional<CatchPlanner> planner;
    std::optional<Eigen::Vector3d> cup;
    bool camera_ready = false;  // vision has the board's pose: the arm may come into view
    Mailbox<catch_world_t> worlds;
    std::atomic<int64_t> goals{0}, bad_messages{0};
    const int64_t run_id = wall_us();  // goal ids unique across restarts

    bus.subscribe<catch_survey_t>(catching::channels::kSurvey, [&](const catch_survey_t& m) {
      std::string why;
      const auto placement = placement_from_survey(board, m.board_mm, m.world_mm, why);
      std::lock_guard<std::mutex> lock(mutex);
      if (!placement) {
        ++bad_messages;
        spdlog::warn("CATCH_SURVEY ignored: {}", why);
        return;
      }
      if (!planner) {
        planner.emplace(board, *placement,
                        tuning.apply(CatchPlannerParams::for_board(board, *placement)));
        const auto& r = planner->ready_point_w_mm();
        spdlog::info("board surveyed; ready point ({:.0f}, {:.0f}, {:.0f}) mm", r.x(), r.y(),
                     r.z());
      }
    });
    bus.subscribe<catch_board_pose_t>(
        catching::channels::kBoardPose, [&](const catch_board_pose_t& m) {
          std::lock_guard<std::mutex> lock(mutex);
          if (m.valid && !camera_ready)
            spdlog::info("the camera has the board: moving to the ready point");
          camera_ready = camera_ready || m.valid;
        });
    bus.subscribe<arm_state_t>(ephor::channels::kArmState, [&](const arm_state_t& m) {
      const auto p = cup_of(m);
      if (!p) return;
      std::lock_guard<std::mutex> lock(mutex);
      cup = p;
    });
    bus.subscribe<catch_world_t>(catching::channels::kWorld, [&](const catch_world_t& m) {
      worlds.put(m);
      runtime.trigger("plan");
    });

    runtime.add_triggered("plan", std::chrono::milliseconds(8), [&] {
      const auto world = worlds.take();
      if (!world) return;
      std::lock_guard<std::mutex> lock(mutex);
      if (!planner || !cup || !camera_ready) return;
      bool bad = false;
      const std::optional<CatchPrediction> prediction = prediction_of(*world, &bad);
      if (bad) ++bad_messages;
      const CatchGoal g = planner->step(wall_us(), prediction, *cup);
      if (!g.send) return;
      arm_goal_t msg = goal_message_of(g, *world, run_id);
      msg.utime = wall_us();
      bus.publish(ephor::channels::kArmGoal, msg);
      ++goals;
      spdlog::debug("goal {} ({}): ({:.0f}, {:.0f}, {:.0f}) mm{}", g.goal_id, to_string(g.reason),
                    g.point_w_mm.x(), g.point_w_mm.y(), g.point_w_mm.z(),
                    g.clamped ? " (clamped to the reachable strip)" : "");
    });

    runtime.start();
    spdlog::info("ready: waiting for the board survey (CATCH_SURVEY) and the arm (ARM_STATE)");
    wait_for_shutdown_signal(duration_s);
    runtime.stop();
    spdlog::info("summary: {} goals sent, {} bad messages", goals.load(), bad_messages.load());
  } catch (const ephor::ConfigError& e) {
    // A file given on the command line is bad: one line, status 2 (issue 18).
    std::cerr << "ephor-catch-prim: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
  return 0;
}
