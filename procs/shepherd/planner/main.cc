// ephor-planner: the shepherd's executive (paper 003, section 3.4). Keeps the
// newest OBJECTS and ARM_STATE, runs one planning job (triggered task "plan")
// per objects update (motion_done events are taken in by the next job), and
// sends at most one ARM_GOAL at a time, in image coordinates as the paper's
// planner did. Reports what it is doing on PLANNER_STATUS every job.
//
//   ephor-planner [--planner single|multi|lookahead] [--arm-speed-mm-s S]
//                 [--calibration FILE] [process flags]

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include "common/arm/arm_workcell.h"
#include "common/calibration/field_calibration.h"
#include "common/config/repo_paths.h"
#include "common/config/text_proto.h"
#include "common/geometry/workcell_file.h"
#include "common/lcm/bus.h"
#include "common/lcm/channels.h"
#include "common/log/log.h"
#include "common/runtime/process_args.h"
#include "common/runtime/task_runtime.h"
#include "common/time/clock.h"
#include "ephor/arm_goal_t.hpp"
#include "ephor/arm_state_t.hpp"
#include "ephor/motion_done_t.hpp"
#include "ephor/shepherd_object_t.hpp"
#include "ephor/shepherd_objects_t.hpp"
#include "ephor/shepherd_planner_cmd_t.hpp"
#include "ephor/shepherd_planner_status_t.hpp"
#include "procs/shepherd/planner/planner.h"
#include "procs/shepherd/planner/planner_messages.h"
#include "procs/shepherd/planner/workcell_agreement.h"

namespace {

using ephor::calibration::FieldCalibration;
namespace planner = ephor::planner;

// motion_done events, written by the LCM thread, drained by the plan job.
class DoneQueue {
 public:
  struct Done {
    int64_t goal_id;
    bool ok;
    // Capture time (utime) of the newest OBJECTS received before this
    // motion_done: a goal after it must come from a newer frame.
    int64_t objects_utime;
  };
  void push(const Done& done) {
    std::lock_guard<std::mutex> lock(mutex_);
    events_.push_back(done);
  }
  std::vector<Done> take() {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<Done> out;
    out.swap(events_);
    return out;
  }

 private:
  std::mutex mutex_;
  std::vector<Done> events_;
};

// One planning job: newest objects and arm state in, at most one goal out.
class PlanJob {
 public:
  PlanJob(ephor::Bus& bus, std::unique_ptr<planner::Planner> p, FieldCalibration calibration,
          planner::ArmModel arm_model, ephor::geometry::Workcell workcell,
          std::shared_ptr<ephor::Mailbox<ephor::shepherd_objects_t>> objects,
          std::shared_ptr<ephor::Mailbox<ephor::arm_state_t>> arm_state,
          std::shared_ptr<ephor::Mailbox<ephor::shepherd_planner_cmd_t>> planner_cmd,
          std::shared_ptr<DoneQueue> done, planner::PlannerConfig config)
      : bus_(bus),
        planner_(std::move(p)),
        config_(std::move(config)),
        calibration_(std::move(calibration)),
        arm_model_(arm_model),
        workcell_(workcell),
        agreement_(workcell),
        objects_(std::move(objects)),
        arm_state_(std::move(arm_state)),
        planner_cmd_(std::move(planner_cmd)),
        done_(std::move(done)) {}

  void operator()() {
    const int64_t start_ns = ephor::mono_ns();
    apply_planner_cmd();
    for (const auto& d : done_->take()) {
      if (!planner_->on_motion_done(planner::planner_goal_id(d.goal_id, goal_id_offset_), d.ok)) {
        spdlog::debug("motion_done for goal {} ignored (not the goal outstanding)", d.goal_id);
      } else if (!d.ok) {
        spdlog::debug("goal {} failed; replanning after a back-off", d.goal_id);
      }
      stale_until_utime_ = std::max(stale_until_utime_, d.objects_utime);
    }
    const auto objects = objects_->latest();
    if (!objects) return;  // nothing seen yet (a motion_done before the first objects)
    // A job released by a frame that came before the motion_done (queued
    // behind it) waits for the next frame: every goal after a motion comes
    // from a frame newer than its end.
    if (objects->utime <= stale_until_utime_) return;
    planner::Scene scene;
    scene.now_s = static_cast<double>(start_ns) * 1e-9;
    scene.arm = arm_model_;
    if (const auto arm = arm_state_->latest()) {
      if (const auto message =
              agreement_.update(planner::arm_plane(*arm), static_cast<double>(arm->z_mm))) {
        if (agreement_.agrees()) {
          spdlog::info("{}", *message);
        } else {
          spdlog::error("{}", *message);
        }
      }
      if (!agreement_.agrees()) {  // no goals against another work cell
        planner::PlannerStatus st = planner_->status();
        st.phase = "workcell mismatch";
        publish_status(st, objects->utime, 0.0f);
        return;
      }
      if (const auto model = planner::arm_model_of(*arm, arm_model_, workcell_)) {
        scene.arm = *model;
      } else {
        ++bad_arm_states_;
        spdlog::warn("arm_state with a non-finite tool position ignored ({} so far)",
                     bad_arm_states_);
      }
    } else if (!warned_no_arm_) {
      warned_no_arm_ = true;
      spdlog::warn("no {} yet: assuming the arm is parked at ({}, {}) mm",
                   ephor::channels::kArmState, arm_model_.x_mm, arm_model_.y_mm);
    }
    scene.sheep.reserve(objects->objects.size());
    for (const ephor::shepherd_object_t& o : objects->objects) {
      if (const auto s = planner::sheep_of(o)) {
        scene.sheep.push_back(*s);
      } else {
        ++bad_objects_;
        spdlog::warn("object {} with unknown state {} ignored ({} so far)", o.id,
                     static_cast<int>(o.state), bad_objects_);
      }
    }

    const auto goal = planner_->plan(scene);
    const planner::PlannerStatus st = planner_->status();
    if (st.bad_sheep != reported_bad_sheep_) {
      spdlog::warn("{} object(s) with non-finite position or velocity ignored so far",
                   st.bad_sheep);
      reported_bad_sheep_ = st.bad_sheep;
    }
    if (goal) publish_goal(*goal, objects->utime);
    publish_status(st, objects->utime,
                   static_cast<float>(static_cast<double>(ephor::mono_ns() - start_ns) * 1e-3));
  }

 private:
  void publish_goal(const planner::Goal& goal, int64_t source_utime) {
    ephor::arm_goal_t msg =
        planner::goal_message_of(goal, calibration_, goal_id_offset_, source_utime);
    msg.utime = ephor::wall_us();
    bus_.publish(ephor::channels::kArmGoal, msg);
    spdlog::info("goal {} {} plane ({:.0f}, {:.0f}) mm = ({:.1f}, {:.1f}) px, sheep {}",
                 goal.goal_id + goal_id_offset_,
                 goal.plane == planner::Plane::kObject ? "object" : "elevation", goal.x_mm,
                 goal.y_mm, msg.u, msg.v, goal.target);
  }

  // PLANNER_CMD (from ephor-display): switch planners between jobs. The new
  // planner starts with no goal outstanding; its goal ids are offset so a
  // late motion_done for the old planner's goal can never match one of its own
  // (comm queues the new goal behind a goal already sent, so the arm is never
  // given two at once).
  void apply_planner_cmd() {
    const auto cmd = planner_cmd_->latest();
    if (!cmd || cmd->header.utime == applied_cmd_utime_) return;
    applied_cmd_utime_ = cmd->header.utime;
    if (cmd->planner == planner_->kind()) return;
    try {
      auto next = planner::make_planner(cmd->planner, config_);
      spdlog::info("planner switched from {} to {} (PLANNER_CMD from {})", planner_->kind(),
                   cmd->planner, cmd->header.sender);
      planner_ = std::move(next);
      goal_id_offset_ += kGoalIdOffsetPerSwitch;
    } catch (const std::invalid_argument& e) {
      spdlog::warn("PLANNER_CMD from {} ignored: {}", cmd->header.sender, e.what());
    }
  }

  void publish_status(const planner::PlannerStatus& st, int64_t source_utime, float planning_us) {
    ephor::shepherd_planner_status_t msg = planner::status_message_of(
        st, planner_->kind(), calibration_, goal_id_offset_, source_utime, planning_us);
    bus_.publish(ephor::channels::kPlannerStatus, msg);
  }

  ephor::Bus& bus_;
  static constexpr int64_t kGoalIdOffsetPerSwitch = 1'000'000'000;

  std::unique_ptr<planner::Planner> planner_;
  planner::PlannerConfig config_;
  FieldCalibration calibration_;
  planner::ArmModel arm_model_;
  ephor::geometry::Workcell workcell_;
  planner::WorkcellAgreement agreement_;
  std::shared_ptr<ephor::Mailbox<ephor::shepherd_objects_t>> objects_;
  int64_t stale_until_utime_ = INT64_MIN;  // see DoneQueue::Done::objects_utime
  std::shared_ptr<ephor::Mailbox<ephor::arm_state_t>> arm_state_;
  std::shared_ptr<ephor::Mailbox<ephor::shepherd_planner_cmd_t>> planner_cmd_;
  std::shared_ptr<DoneQueue> done_;
  // Goal ids on ARM_GOAL are unique across restarts of this process (as the
  // catching Prim's): a restarted planner counts its goals from 1 again, and
  // a late MOTION_DONE of the old process's goal 2 must not finish the new
  // one's (issue 18's fault test found the ids repeated).
  int64_t goal_id_offset_ = ephor::wall_us();
  int64_t applied_cmd_utime_ = -1;  // header.utime of the newest PLANNER_CMD looked at
  bool warned_no_arm_ = false;
  int64_t bad_objects_ = 0;
  int64_t bad_arm_states_ = 0;
  int64_t reported_bad_sheep_ = 0;
};

}  // namespace

int main(int argc, char** argv) {
  ephor::block_shutdown_signals();
  CLI::App app{"ephor-planner: the shepherd's planner (paper 003, section 3.4)"};
  ephor::ProcessArgs args;
  ephor::add_process_flags(app, args, "planner");
  std::string kind = "multi";
  std::string calibration_path;
  planner::PlannerConfig config;
  planner::ArmModel arm_model;
  double deadline_ms = 20.0;
  double budget_ms = config.lookahead_budget_s * 1e3;
  app.add_option("--planner", kind, "single, multi or lookahead")
      ->check(CLI::IsMember(planner::planner_kinds()));
  app.add_option("--arm-speed-mm-s", arm_model.speed_mm_s,
                 "end-effector speed the planner assumes when timing intercepts, mm/s "
                 "(goals ask for the arm's default speed)")
      ->check(CLI::Range(1.0, 5000.0));
  std::string workcell_path;
  app.add_option("--workcell", workcell_path,
                 "work cell file (common/geometry/workcell.proto), the same file the manifest "
                 "gives ephor-arm and ephor-sim; default: the shepherding field");
  app.add_option("--calibration", calibration_path,
                 "image-to-field calibration (Protobuf text); default "
                 "deploy/calibration/sim.pbtxt in the repository");
  app.add_option("--lookahead-depth", config.lookahead_depth, "saves searched ahead (lookahead)")
      ->check(CLI::Range(1, 12));
  app.add_option("--lookahead-budget-ms", budget_ms, "search time per job, ms (lookahead)")
      ->check(CLI::Range(0.01, 1000.0));
  app.add_option("--deadline-ms", deadline_ms, "deadline of the plan task, ms")
      ->check(CLI::PositiveNumber);
  if (const auto exit_status = ephor::parse_flags(app, argc, argv)) return *exit_status;
  ephor::init_logging(args.name);
  config.lookahead_budget_s = budget_ms * 1e-3;
  // Until ARM_STATE arrives the arm is assumed where ephor-arm parks it.
  arm_model.x_mm = config.park_x_mm;
  arm_model.y_mm = config.park_y_mm;

  try {
    if (calibration_path.empty()) calibration_path = ephor::default_calibration_path();
    auto calibration = FieldCalibration::load(calibration_path);
    spdlog::info("calibration {} ({})", calibration_path, calibration.source());
    config.workcell = ephor::geometry::workcell_from_flag(workcell_path);
    if (!workcell_path.empty()) spdlog::info("work cell {}", workcell_path);
    if (const std::string why = planner::calibration_disagreement(
            config.workcell, calibration.plane_z_mm(ephor::calibration::Plane::kObject),
            calibration.plane_z_mm(ephor::calibration::Plane::kElevation));
        !why.empty()) {
      spdlog::error("calibration {} does not fit the work cell {}: {}", calibration_path,
                    workcell_path.empty() ? "(default)" : workcell_path, why);
      return 2;
    }

    ephor::Bus bus(args.lcm_url, args.name);
    ephor::TaskRuntime runtime(bus, {args.name, args.host, !args.no_mlock});
    auto objects = std::make_shared<ephor::Mailbox<ephor::shepherd_objects_t>>();
    auto arm_state = bus.mailbox<ephor::arm_state_t>(ephor::channels::kArmState);
    auto planner_cmd = bus.mailbox<ephor::shepherd_planner_cmd_t>(ephor::channels::kPlannerCmd);
    auto done = std::make_shared<DoneQueue>();
    auto job = std::make_shared<PlanJob>(bus, planner::make_planner(kind, config),
                                         std::move(calibration), arm_model, config.workcell,
                                         objects, arm_state, planner_cmd, done, config);
    runtime.add_triggered("plan", std::chrono::nanoseconds(static_cast<int64_t>(deadline_ms * 1e6)),
                          [job] { (*job)(); });
    bus.subscribe<ephor::shepherd_objects_t>(
        ephor::channels::kObjects, [objects, &runtime](const ephor::shepherd_objects_t& msg) {
          objects->put(msg);
          runtime.trigger("plan");
        });
    bus.subscribe<ephor::motion_done_t>(
        ephor::channels::kMotionDone,
        [done, objects, failures = std::make_shared<int64_t>(0)](const ephor::motion_done_t& msg) {
          const auto seen = objects->latest();
          done->push({msg.goal_id, msg.status == ephor::motion_done_t::STATUS_DONE,
                      seen ? seen->utime : INT64_MIN});
          // The first failures in full, then every 100th (a broken arm fails every goal).
          if (msg.status != ephor::motion_done_t::STATUS_DONE &&
              (++*failures <= 20 || *failures % 100 == 0)) {
            spdlog::warn("goal {} ended with status {}: {} ({} failed goals so far)", msg.goal_id,
                         static_cast<int>(msg.status), msg.reason, *failures);
          }
          // No job here: the next goal is planned when the next OBJECTS
          // arrives (at most one frame, 33 ms, later), so every goal comes
          // from a frame newer than the motion it follows, its capture-to-
          // command latency is the pipeline's, and with vision paused the
          // arm stops after its current motion instead of acting on old
          // objects.
        });
    runtime.start();
    spdlog::info("{} planner: {} -> {}", kind, ephor::channels::kObjects,
                 ephor::channels::kArmGoal);
    ephor::wait_for_shutdown_signal();
    runtime.stop();
  } catch (const ephor::ConfigError& e) {
    // A file given on the command line is bad: one line, status 2 (issue 18).
    std::cerr << "ephor-planner: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
  return 0;
}
