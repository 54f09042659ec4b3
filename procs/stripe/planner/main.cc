// ephor-stripe-planner: the `scan planner` of the light-stripe system (paper
// 004, sections 1 and 5): moves the sensor over a region in a regular raster
// of stripes (the paper's 10 mm steps), one joint goal per stripe to the
// shared arm through comm, an image at rest at each (STRIPE_CAPTURE), the
// next goal sent as soon as the image is taken so that the arm moves while
// the stripe and range processes work on it (ScanSequencer). Everything is
// checked before the arm moves (RasterPlan): the region's corners and every
// stripe within reach and clear, the calibration file this robot's.
//
//   ephor-stripe-planner --region X0,Y0,X1,Y1 [--step-mm 10] [--height-mm 300]
//                        [--calibration FILE] [--robot-seed N] [--scans N] [--summary FILE]
//   ephor-stripe-planner --check [--scene FILE.obj] ...   (the same checks, then exit: 0 or 2)
//
//   subscribes  ARM_STATE, MOTION_DONE, STRIPE_IMAGE, STRIPE_POINTS, STRIPE_PROFILE, STRIPE_CLOUD
//   publishes   ARM_GOAL (arm_goal_t, KIND_JOINTS), STRIPE_CAPTURE, STRIPE_SCAN (on every
//               change and once a second)
//   tasks       plan (triggered by each event it waits for; also every 100 ms for timeouts)
//
// Ends (exit 0) when --scans scans are done (0 = scan again and again,
// --pause-s apart); exit 1 when a scan fails, 2 on bad input (one line).

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include "common/config/repo_paths.h"
#include "common/config/text_proto.h"
#include "common/geometry/workcell_file.h"
#include "common/lcm/bus.h"
#include "common/lcm/channels.h"
#include "common/log/log.h"
#include "common/runtime/process_args.h"
#include "common/runtime/task_runtime.h"
#include "common/stripe/calibration_file.h"
#include "common/stripe/stripe_channels.h"
#include "common/stripe/stripe_messages.h"
#include "common/stripe/stripe_scene.h"
#include "common/time/clock.h"
#include "ephor/arm_goal_t.hpp"
#include "ephor/arm_state_t.hpp"
#include "ephor/motion_done_t.hpp"
#include "ephor/stripe_capture_t.hpp"
#include "ephor/stripe_cloud_t.hpp"
#include "ephor/stripe_image_t.hpp"
#include "ephor/stripe_points_t.hpp"
#include "ephor/stripe_profile_t.hpp"
#include "ephor/stripe_scan_t.hpp"
#include "procs/stripe/planner/plan_task.h"
#include "procs/stripe/planner/planner_messages.h"
#include "procs/stripe/planner/raster_plan.h"
#include "procs/stripe/planner/scan_sequencer.h"

namespace {

using namespace ephor;
using namespace ephor::stripe;

double now_s() { return static_cast<double>(mono_ns()) * 1e-9; }

}  // namespace

int main(int argc, char** argv) {
  block_shutdown_signals();
  CLI::App app{"ephor-stripe-planner: scans a region in a raster of stripes with the arm"};
  ProcessArgs args;
  add_process_flags(app, args, "planner");
  std::string region = "-200,-200,200,200", calibration_path, scene_path, summary_path,
              workcell_path = "deploy/stripe/workcell.pbtxt", along = "y";
  RasterSpec spec;
  // Passes 60 mm long: across an object standing 100 mm tall the stripe
  // breaks where it steps up, and only its tallest top-to-bottom piece is
  // kept (section 2), so shorter passes keep more of the objects.
  spec.pass_length_mm = 60.0;
  int robot_seed = 0, scans = 1;
  bool check = false;
  double pause_s = 3.0, speed_mm_s = 0.0, duration_s = 0.0;
  app.add_option("--region", region, "X0,Y0,X1,Y1: the region to scan, mm, table frame")
      ->capture_default_str();
  app.add_option("--step-mm", spec.step_mm, "between stripes, mm (default 10, the paper's)")
      ->check(CLI::Range(0.1, 1000.0));
  app.add_option("--height-mm", spec.height_mm,
                 "the projector above the table, mm (default 300, the paper's range)")
      ->check(CLI::Range(50.0, 1000.0));
  app.add_option("--pass-length-mm", spec.pass_length_mm,
                 "the length of stripe used per pass along its direction, mm (default 60)")
      ->check(CLI::Range(10.0, 200.0));
  app.add_option("--stripes-along", along, "x or y: the stripes' direction (default y)");
  app.add_option("--calibration", calibration_path,
                 "calibration file (default: the nominal arm and the cage from the drawings)");
  app.add_option("--robot-seed", robot_seed, "the robot this is (the calibration must be its)")
      ->check(CLI::Range(0, 1000000));
  app.add_option("--workcell", workcell_path,
                 "work cell file (default deploy/stripe/workcell.pbtxt)");
  app.add_option("--scene", scene_path, "--check: the scene file the simulator will load");
  app.add_flag("--check", check, "check the inputs (region, calibration, scene), then exit");
  app.add_option("--scans", scans, "scans to make, then exit (0 = until stopped; default 1)")
      ->check(CLI::Range(0, 1000000));
  app.add_option("--pause-s", pause_s, "between scans, s (default 3)")
      ->check(CLI::Range(0.0, 3600.0));
  app.add_option("--speed-mm-s", speed_mm_s,
                 "tool speed asked of the arm, mm/s (0 = its default; the arm refuses below 10)")
      ->check(CLI::Range(0.0, 10000.0))
      ->check(CLI::Validator(
          [](std::string& text) -> std::string {
            const double v = std::strtod(text.c_str(), nullptr);
            return v == 0.0 || v >= 10.0 ? "" : "below the arm's 10 mm/s (0 = its default)";
          },
          "0 or >= 10"));
  app.add_option("--summary", summary_path, "write the last scan's JSON summary here");
  app.add_option("--duration", duration_s, "exit after this many seconds (0 = when done)")
      ->check(CLI::Range(0.0, 1e7));
  if (const auto exit_status = ephor::parse_flags(app, argc, argv)) return *exit_status;
  if (along != "x" && along != "y") {
    std::cerr << "ephor-stripe-planner: --stripes-along " << along << ": want x or y\n";
    return 2;
  }
  spec.stripes_along_y = along == "y";

  // The checks a person's input gets before anything moves: one line, status 2.
  geometry::Workcell workcell;
  StripeCalibration calibration;
  RasterPlan plan;
  try {
    parse_region(region, spec);
    workcell = geometry::load_workcell_file(resolve_repo_path(workcell_path));
    calibration = calibration_from_flags(calibration_path, robot_seed);
    if (!scene_path.empty()) StripeScene::load(resolve_repo_path(scene_path));
    plan = plan_raster(spec, workcell, calibration.arm_model(), calibration.sensor);
  } catch (const std::exception& e) {
    std::cerr << "ephor-stripe-planner: " << e.what() << "\n";
    return 2;
  }
  if (check) {
    std::cout << "ok: " << plan.goals.size() << " stripes " << spec.step_mm << " mm apart over ("
              << spec.x0_mm << ", " << spec.y0_mm << ") - (" << spec.x1_mm << ", " << spec.y1_mm
              << ") mm, " << calibration.measured << "\n";
    return 0;
  }
  init_logging(args.name);

  try {
    Bus bus(args.lcm_url, args.name);
    TaskRuntime runtime(bus, {args.name, args.host, !args.no_mlock});
    std::mutex mutex;
    std::vector<PlanEvent> events;
    std::optional<arm::Joints> arm_q;
    bool arm_moving = false;
    std::atomic<bool> finished{false};

    auto push = [&](PlanEvent e) {
      {
        std::lock_guard<std::mutex> lock(mutex);
        events.push_back(std::move(e));
      }
      runtime.trigger("plan");
    };
    bus.subscribe<arm_state_t>(ephor::channels::kArmState, [&](const arm_state_t& m) {
      const std::optional<arm::Joints> q = arm_joints_of(m);
      if (!q) return;
      std::lock_guard<std::mutex> lock(mutex);
      arm_q = *q;
      arm_moving = m.moving;
    });
    bus.subscribe<motion_done_t>(ephor::channels::kMotionDone,
                                 [&](const motion_done_t& m) { push(event_of(m)); });
    bus.subscribe<stripe_image_t>(stripe::channels::kImage, [&](const stripe_image_t& m) {
      if (auto e = event_of(m, args.name)) push(std::move(*e));
    });
    bus.subscribe<stripe_points_t>(stripe::channels::kPoints,
                                   [&](const stripe_points_t& m) { push(event_of(m)); });
    bus.subscribe<stripe_profile_t>(stripe::channels::kProfile,
                                    [&](const stripe_profile_t& m) { push(event_of(m)); });
    bus.subscribe<stripe_cloud_t>(stripe::channels::kCloud,
                                  [&](const stripe_cloud_t& m) { push(event_of(m)); });

    // The task's answers, on the bus.
    class BusOutputs : public PlanOutputs {
     public:
      explicit BusOutputs(Bus& bus) : bus_(bus) {}
      void goal(const GoalAction&, arm_goal_t m) override {
        bus_.publish(ephor::channels::kArmGoal, m);
      }
      void capture(const CaptureAction&, stripe_capture_t m) override {
        bus_.publish(stripe::channels::kCapture, m);
      }
      void scan(stripe_scan_t m) override { bus_.publish(stripe::channels::kScan, m); }

     private:
      Bus& bus_;
    } outputs(bus);
    PlanTaskConfig config;
    config.spec = spec;
    config.speed_mm_s = speed_mm_s;
    config.scans = scans;
    config.pause_s = pause_s;
    config.plan = [&](const arm::Joints& from) {
      return plan_raster(spec, workcell, calibration.arm_model(), calibration.sensor, from);
    };
    config.wall_us = [] { return wall_us(); };
    config.robot_seed = robot_seed;
    config.calibration_name = calibration_path.empty() ? "drawing" : calibration_path;
    config.calibration_measured = calibration.measured;
    config.summary_path = summary_path;
    // The scan in hand (task thread only).
    PlanTask task(std::move(config), outputs, wall_us());

    auto job = [&] {
      std::vector<PlanEvent> batch;
      std::optional<arm::Joints> q;
      bool moving = false;
      {
        std::lock_guard<std::mutex> lock(mutex);
        batch.swap(events);
        q = arm_q;
        moving = arm_moving;
      }
      task.run(now_s(), batch, q, moving);
      if (task.finished()) finished = true;
    };
    runtime.add_triggered("plan", std::chrono::milliseconds(50), job);
    runtime.add_periodic("tick", std::chrono::milliseconds(100), [&] { runtime.trigger("plan"); });

    runtime.start();
    spdlog::info(
        "ready: {} stripes planned over ({:g}, {:g}) - ({:g}, {:g}) mm, robot seed {}; "
        "waiting for the arm",
        plan.goals.size(), spec.x0_mm, spec.y0_mm, spec.x1_mm, spec.y1_mm, robot_seed);
    const int64_t end_ns =
        duration_s > 0 ? mono_ns() + static_cast<int64_t>(duration_s * 1e9) : INT64_MAX;
    while (!finished && mono_ns() < end_ns) {
      if (wait_for_shutdown_signal(0.05) != 0) break;
    }
    runtime.stop();
    return task.exit_code();
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
}
