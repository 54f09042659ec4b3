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

namespace {
// ARM_GOAL to the arm's servo through comm, about: a reaching trajectory
// starts where the arm will be then, s.
constexpr double kLatencyS = 0.03;
// No re-plan this close before a reaching trajectory lands, s (see below).
constexpr double kReplanBeforeLandS = 0.3;
// The arm is on the trajectory sent when its state is this near it, rad
// (ephor-arm refuses a trajectory starting more than 0.05 rad off).
constexpr double kOnTrackRad = 0.02;
}  // namespace

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
    TaggingPlanner planner(cell, options);
    Bus bus(args.lcm_url, args.name);
    TaskRuntime runtime(bus, {args.name, args.host, !args.no_mlock});
    std::mutex mutex;
    std::optional<FittedMotion> motion;
    int64_t motion_utime = 0;
    std::optional<arm::Joints> q_now, qd_now;
    // The reaching trajectory sent last: its diode and when it ends (wall
    // clock, us); none is sent while it runs.
    int trajectory_task = -2;
    int64_t trajectory_end_utime = 0, trajectory_land_utime = 0, trajectory_motion_utime = 0;
    int64_t state_utime = 0;  // of q_now, qd_now
    std::atomic<int64_t> trajectories{0}, trajectory_failures{0};
    std::vector<bool> tagged(static_cast<std::size_t>(diodes), false);
    std::atomic<int64_t> goals{0}, bad{0};
    const int64_t run_id = wall_us();
    int last_task = -2, sent_task = -2;
    std::optional<arm::Joints> sent_goal;
    std::string last_status;
    std::vector<int> logged_order{-1};
    std::optional<TaggingTrajectory> sent_trajectory;  // the last reaching trajectory sent
    std::atomic<int64_t> replans{0};                   // of them, re-planned from the one running
    bool looking = false;  // sent back to the viewing pose since the prediction went stale

    bus.subscribe<rambo_prediction_t>(
        rambo::channels::kPrediction, [&](const rambo_prediction_t& m) {
          if (!m.fitted) return;
          std::string why;
          const std::optional<FittedMotion> f =
              motion_from_message(m, static_cast<double>(m.ref_utime) * 1e-6, &why);
          if (!f) {
            ++bad;
            spdlog::warn("RAMBO_PREDICTION from {} ignored: {}", m.header.sender, why);
            return;
          }
          std::lock_guard<std::mutex> lock(mutex);
          motion = *f;
          motion_utime = m.ref_utime;
        });
    bus.subscribe<rambo_indicator_t>(rambo::channels::kIndicator, [&](const rambo_indicator_t& m) {
      if (m.num_diodes != diodes || static_cast<int>(m.tagged.size()) != diodes) {
        ++bad;
        return;
      }
      std::lock_guard<std::mutex> lock(mutex);
      for (int i = 0; i < diodes; ++i)
        tagged[static_cast<std::size_t>(i)] = m.tagged[static_cast<std::size_t>(i)];
    });
    bus.subscribe<arm_state_t>(ephor::channels::kArmState, [&](const arm_state_t& m) {
      arm::Joints q;
      arm::Joints qd;
      for (int j = 0; j < 6; ++j) q[j] = m.q[j], qd[j] = m.qd[j];
      if (!q.allFinite() || !qd.allFinite()) return;
      std::lock_guard<std::mutex> lock(mutex);
      q_now = q;
      qd_now = qd;
      state_utime = m.utime;
    });

    runtime.add_periodic(
        "plan", std::chrono::microseconds(static_cast<int64_t>(period_ms * 1e3)), [&] {
          rambo_plan_t plan{};
          std::optional<arm::Joints> goal, look_goal;
          int64_t source_utime = 0;
          {
            std::lock_guard<std::mutex> lock(mutex);
            const int64_t now = wall_us();
            plan.utime = now;
            plan.current_task = -1;
            if (!motion || !q_now) {
              plan.status = "waiting for a prediction and the arm";
            } else if (static_cast<double>(now - motion_utime) * 1e-6 >
                       (motion->polynomial ? max_prediction_age_s : max_rigid_prediction_age_s)) {
              plan.status = "prediction too old";
              // The camera is on the tool: after a reach that lost the
              // target (a wrong pose, or the tumble turning it away) no
              // frame shows it again while the arm waits where it is. Once
              // per loss, back to the start pose, whose view holds the whole
              // target (RamboCell), when no trajectory is running.
              if (!looking && now >= trajectory_end_utime &&
                  (*q_now - cell.start_joints).cwiseAbs().maxCoeff() > arrive_rad) {
                looking = true;
                look_goal = cell.start_joints;
                plan.status = "prediction too old: back to the viewing pose";
                trajectory_task = -2;
              }
            } else {
              looking = false;
              const TaggingStep s =
                  planner.step(static_cast<double>(now) * 1e-6, *motion, tagged, *q_now);
              plan.status = s.status;
              plan.current_task = s.task;
              plan.order = s.order;
              plan.greedy_trajectories = s.greedy_trajectories;
              plan.exhaustive_trajectories = s.exhaustive_trajectories;
              plan.dp_trajectories = s.dp_trajectories;
              plan.order_total_s = std::isfinite(s.order_total_s) ? s.order_total_s : -1.0;
              goal = s.goal_q;
              source_utime = motion_utime;
              if (s.reordered && s.order != logged_order) {
                logged_order = s.order;
                std::string order;
                for (int i : s.order) order += " " + cell.diodes[static_cast<std::size_t>(i)].name;
                spdlog::info(
                    "order:{}; reaching trajectories computed: greedy {}, exhaustive {}, "
                    "DP {}",
                    order, s.greedy_trajectories, s.exhaustive_trajectories, s.dp_trajectories);
              }
            }
            if (plan.current_task != last_task || plan.status != last_status) {
              spdlog::info("{}", plan.status);
              last_task = plan.current_task;
              last_status = plan.status;
            }
          }
          plan.num_tasks = static_cast<int32_t>(plan.order.size());
          // Reaching trajectories: one per diode, a new one only when the
          // last has ended (its hold over) and the diode is still open.
          std::optional<TaggingTrajectory> reaching;
          if (goal && reach == "trajectory") {
            std::lock_guard<std::mutex> lock(mutex);
            const int64_t now = wall_us();
            // While the arm is on a trajectory to this diode (reaching or
            // holding), each newer prediction re-plans it (section 8: "the
            // reaching trajectory ... should be recomputed based on the new
            // goal trajectory, and the present joint trajectory, which may
            // itself be a reaching trajectory"): the new one leaves the
            // trajectory being executed where the arm will be on it when the
            // goal arrives, in position and velocity.
            // Not in the last kReplanBeforeLandS before landing: the arm
            // is then near the goal trajectory anyway, and fast, so the
            // new start would be furthest from where the arm really is
            // (the arm refuses a start more than 0.05 rad off); it
            // re-plans again once on the goal point.
            const bool on_it = plan.current_task == trajectory_task && sent_trajectory &&
                               now < trajectory_end_utime;
            const bool landing =
                now < trajectory_land_utime &&
                now > trajectory_land_utime - std::llround(kReplanBeforeLandS * 1e6);
            if (on_it && (motion_utime == trajectory_motion_utime || landing)) {
              goal.reset();  // the arm is on it
            } else {
              std::string why;
              // Starts where the arm will be when it gets it: the state
              // extrapolated to now + the relay's latency (or the running
              // trajectory then).
              const double t0_s = static_cast<double>(now) * 1e-6 + kLatencyS;
              const double ahead_s = t0_s - static_cast<double>(state_utime) * 1e-6;
              const arm::Joints q0 = *q_now + *qd_now * std::clamp(ahead_s, 0.0, 0.2);
              // Only from the trajectory the arm is really on: a refused
              // one (the arm checks the start within 0.05 rad) is not run,
              // and re-planning from it would drift further from the arm at
              // every step (seen: 138 of 167 refused, starts 0.05-0.33 rad
              // off, the arm standing still meanwhile).
              const bool from_running =
                  on_it && (sent_trajectory->at(t0_s).q - q0).cwiseAbs().maxCoeff() < kOnTrackRad;
              // Still reaching but off the sent trajectory (the arm started
              // it late, or refused it): no re-plan, as before section 8's
              // was done here; the arm's state extrapolated while it is fast
              // would start too far from it.
              const bool reaching_off_track = on_it && !from_running && now < trajectory_land_utime;
              if (!reaching_off_track)
                reaching = planner.reaching_trajectory(plan.current_task, t0_s, *motion, q0,
                                                       *qd_now, &why, limit_fraction,
                                                       from_running ? &*sent_trajectory : nullptr);
              if (!reaching && on_it) {
                // No better one from here: the arm stays on the one it has.
                trajectory_motion_utime = motion_utime;
                goal.reset();
              }
              if (reaching) {
                if (from_running) ++replans;
                sent_trajectory = reaching;
                trajectory_task = plan.current_task;
                trajectory_end_utime = std::llround(reaching->end_s() * 1e6);
                trajectory_land_utime = std::llround(reaching->t_land_s * 1e6);
                trajectory_motion_utime = motion_utime;
                spdlog::info(
                    "{}reaching trajectory to diode {}: lands in {:.2f} s{} ({} durations tried), "
                    "then {:.1f} s on the goal point",
                    on_it ? "re-planned " : "",
                    cell.diodes[static_cast<std::size_t>(plan.current_task)].name,
                    reaching->t_land_s - reaching->t0_s,
                    reaching->via_intermediate_goal ? " via a safe intermediate goal" : "",
                    reaching->durations_tried, reaching->hold_end_s - reaching->t_land_s);
              } else if (goal) {
                // The point-to-point goal below instead.
                if (++trajectory_failures % 10 == 1)
                  spdlog::warn("no reaching trajectory to diode {} ({}): a joint goal instead",
                               plan.current_task, why);
              }
            }
          }
          // Each goal makes the arm plan anew from rest: while it is still
          // on its way, a goal that has barely moved is not sent again (it
          // would only slow the reach down); once the arm is there, the goal
          // is refreshed every period so that the laser follows the diode.
          if (goal && !reaching) {
            std::lock_guard<std::mutex> lock(mutex);
            const bool arrived =
                sent_goal && q_now && (*q_now - *sent_goal).cwiseAbs().maxCoeff() < arrive_rad;
            const bool moved =
                !sent_goal || (*goal - *sent_goal).cwiseAbs().maxCoeff() > resend_rad;
            if (plan.current_task != sent_task || arrived || moved) {
              sent_goal = goal;
              sent_task = plan.current_task;
            } else {
              goal.reset();
            }
          }
          if (look_goal) {
            goal = look_goal;
            std::lock_guard<std::mutex> lock(mutex);
            sent_goal = goal;
            sent_task = -1;
          }
          if (goal) {
            arm_goal_t g{};
            g.utime = wall_us();
            g.goal_id = run_id + goals;
            g.kind = arm_goal_t::KIND_JOINTS;
            for (int j = 0; j < 6; ++j) g.joints_rad[j] = (*goal)[j];
            if (reaching) {
              g.kind = arm_goal_t::KIND_TRAJECTORY;
              for (std::size_t k = 0; k < reaching->samples.size(); ++k) {
                const JointSample& js = reaching->samples[k];
                g.traj_t_s.push_back(static_cast<float>(reaching->dt_s * static_cast<double>(k)));
                g.traj_q_rad.emplace_back(js.q.data(), js.q.data() + 6);
                g.traj_qd_rad_s.emplace_back(js.qd.data(), js.qd.data() + 6);
              }
              g.num_points = static_cast<int32_t>(g.traj_t_s.size());
              const arm::Joints& last = reaching->samples.back().q;
              for (int j = 0; j < 6; ++j) g.joints_rad[j] = last[j];
              ++trajectories;
            }
            g.max_speed_mm_s = 0.0f;
            g.source_frame_utime = source_utime;
            g.target_object = plan.current_task;
            bus.publish(ephor::channels::kArmGoal, g);
            ++goals;
          }
          plan.goals_sent = goals;
          bus.publish(rambo::channels::kPlan, plan);
        });

    runtime.start();
    spdlog::info("ready: {} diodes, goals every {} ms, lead {} s", diodes, period_ms,
                 options.lead_s);
    wait_for_shutdown_signal(duration_s);
    runtime.stop();
    spdlog::info(
        "summary: {} goals sent ({} reaching trajectories, {} of them re-planned from the one "
        "running), {} bad messages",
        goals.load(), trajectories.load(), replans.load(), bad.load());
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
