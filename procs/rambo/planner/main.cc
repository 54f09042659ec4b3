// ephor-rambo-planner: RAMBO's robot motion planner for laser tagging (paper
// sections 7-10) over TaggingPlanner: orders the untagged diodes (greedy,
// exhaustive, dynamic programming; the DP order is followed) and, for the
// current diode, sends the arm the reaching trajectory (sections 8-9: the
// shortest within the joint limits onto the diode's predicted goal-point
// trajectory, then that trajectory followed for the hold) as one
// KIND_TRAJECTORY goal, which the shared arm checks against its limits and
// executes as given; each newer prediction while the arm is on it re-plans
// it from the trajectory being executed (section 8); when it ends with the
// diode not tagged, a new one from where the arm is. With no fresh
// prediction the arm goes back to the start pose, whose view holds the
// target, so the camera on the tool sees it again. --reach goals streams
// point-to-point joint goals a short lead ahead instead (the earlier way).
// The shared comm (newest goal wins) and arm carry them out; the target's
// indicator says which diodes are done.
//
//   subscribes  RAMBO_PREDICTION (rambo_prediction_t), RAMBO_INDICATOR
//               (rambo_indicator_t), ARM_STATE (arm_state_t)
//   publishes   ARM_GOAL (arm_goal_t, KIND_TRAJECTORY or KIND_JOINTS), RAMBO_PLAN (rambo_plan_t)
//   tasks       plan (periodic, --period-ms)

#include <algorithm>
#include <atomic>
#include <cmath>
#include <iostream>
#include <mutex>
#include <optional>
#include <string>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include "common/config/text_proto.h"
#include "common/lcm/bus.h"
#include "common/lcm/channels.h"
#include "common/log/log.h"
#include "common/rambo/prediction_message.h"
#include "common/rambo/rambo_cell.h"
#include "common/rambo/rambo_channels.h"
#include "common/rambo/tagging_planner.h"
#include "common/rambo/target_model_file.h"
#include "common/runtime/process_args.h"
#include "common/runtime/task_runtime.h"
#include "common/time/clock.h"
#include "ephor/arm_goal_t.hpp"
#include "ephor/arm_state_t.hpp"
#include "ephor/rambo_indicator_t.hpp"
#include "ephor/rambo_plan_t.hpp"
#include "ephor/rambo_prediction_t.hpp"
#include "procs/rambo/planner/planner_task.h"

int main(int argc, char** argv) {
  using namespace ephor;
  using namespace ephor::rambo;
  block_shutdown_signals();
  CLI::App app{"ephor-rambo-planner: diode order and laser goals on the tumbling target"};
  ProcessArgs args;
  add_process_flags(app, args, "planner");
  int diodes = 4;
  double period_ms = 200.0, duration_s = 0.0, max_prediction_age_s = 3.0,
         max_rigid_prediction_age_s = 8.0;
  TaggingOptions options;
  double arrive_rad = 0.03, resend_rad = 0.1;
  std::string model_path;
  app.add_option("--diodes", diodes, "the model's first N diodes are tagged (default 4)")
      ->check(CLI::Range(1, RamboCell::kMaxDiodes));
  app.add_option(
      "--model", model_path,
      "target model file (common/rambo/target_model.proto; default: the built-in target)");
  app.add_option("--period-ms", period_ms, "planning period, ms (default 200)")
      ->check(CLI::Range(20.0, 5000.0));
  app.add_option("--lead-s", options.lead_s, "aim at the goal this far ahead, s (default 0.3)")
      ->check(CLI::Range(0.0, 5.0));
  app.add_option("--max-prediction-age-s", max_prediction_age_s,
                 "no goals from a polynomial prediction older than this, s (default 3)")
      ->check(CLI::Range(0.1, 60.0));
  // A rigid body with constant momenta extrapolates far better than a
  // polynomial (ephor-bench-rambo --sections live-prediction): keeping it
  // lets the arm go on tagging while the camera on the tool looks past the
  // target, instead of going back to the viewing pose after 3 s.
  app.add_option("--max-rigid-prediction-age-s", max_rigid_prediction_age_s,
                 "the same for a rigid-body prediction, s (default 8)")
      ->check(CLI::Range(0.1, 60.0));
  app.add_option("--arrive-rad", arrive_rad,
                 "the arm is at its goal within this, rad: refresh the goal every period (0.03)");
  app.add_option("--resend-rad", resend_rad,
                 "before that, send again only when the goal moved this far, rad (0.1)");
  std::string reach = "trajectory";
  double limit_fraction = 0.8;
  app.add_option(
         "--reach", reach,
         "trajectory (the reaching trajectory of sections 8-9 and the hold, executed by the "
         "arm as given) or goals (point-to-point joint goals every period)")
      ->check(CLI::IsMember({"trajectory", "goals"}));
  app.add_option("--limit-fraction", limit_fraction,
                 "reaching trajectories use this share of the joint speed and acceleration limits "
                 "(0.8)")
      ->check(CLI::Range(0.1, 1.0));
  app.add_option("--duration", duration_s, "exit after this many seconds (0 = until signalled)");
  if (const auto exit_status = ephor::parse_flags(app, argc, argv)) return *exit_status;
  init_logging(args.name);

  try {
    const RamboCell cell = cell_from_flags(model_path, diodes);
    PlannerTaskOptions task_options;
    task_options.diodes = diodes;
    task_options.tagging = options;
    task_options.max_prediction_age_s = max_prediction_age_s;
    task_options.max_rigid_prediction_age_s = max_rigid_prediction_age_s;
    task_options.arrive_rad = arrive_rad;
    task_options.resend_rad = resend_rad;
    task_options.reach_trajectory = reach == "trajectory";
    task_options.limit_fraction = limit_fraction;
    Bus bus(args.lcm_url, args.name);
    TaskRuntime runtime(bus, {args.name, args.host, !args.no_mlock});
    std::mutex mutex;
    PlannerTask task(cell, task_options, wall_us());  // guarded by mutex

    bus.subscribe<rambo_prediction_t>(
        rambo::channels::kPrediction, [&](const rambo_prediction_t& m) {
          std::string why;
          bool read = false;
          {
            std::lock_guard<std::mutex> lock(mutex);
            read = task.on_prediction(m, &why);
          }
          if (!read) spdlog::warn("RAMBO_PREDICTION from {} ignored: {}", m.header.sender, why);
        });
    bus.subscribe<rambo_indicator_t>(rambo::channels::kIndicator, [&](const rambo_indicator_t& m) {
      std::lock_guard<std::mutex> lock(mutex);
      task.on_indicator(m);
    });
    bus.subscribe<arm_state_t>(ephor::channels::kArmState, [&](const arm_state_t& m) {
      std::lock_guard<std::mutex> lock(mutex);
      task.on_arm_state(m);
    });

    runtime.add_periodic("plan", std::chrono::microseconds(static_cast<int64_t>(period_ms * 1e3)),
                         [&] {
                           PlannerTask::Period p;
                           {
                             std::lock_guard<std::mutex> lock(mutex);
                             p = task.period(wall_us);
                           }
                           if (p.goal) bus.publish(ephor::channels::kArmGoal, *p.goal);
                           bus.publish(rambo::channels::kPlan, p.plan);
                         });

    runtime.start();
    spdlog::info("ready: {} diodes, goals every {} ms, lead {} s", diodes, period_ms,
                 options.lead_s);
    wait_for_shutdown_signal(duration_s);
    runtime.stop();
    spdlog::info(
        "summary: {} goals sent ({} reaching trajectories, {} of them re-planned from the one "
        "running), {} bad messages",
        task.goals(), task.trajectories(), task.replans(), task.bad());
  } catch (const ephor::ConfigError& e) {
    // A bad --model file or --diodes: one line, status 2 (issue 18).
    std::cerr << "ephor-rambo-planner: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
  return 0;
}
