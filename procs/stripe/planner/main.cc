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
#include <deque>
#include <fstream>
#include <iostream>
#include <mutex>
#include <optional>
#include <string>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

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
#include "procs/stripe/planner/planner_messages.h"
#include "procs/stripe/planner/raster_plan.h"
#include "procs/stripe/planner/scan_sequencer.h"

namespace {

using namespace ephor;
using namespace ephor::stripe;

// Paper 004, section 5: "a system such as we are discussing should be able to
// image 3 or 4 stripes of 256 three-dimensional points per second if
// scanning is done in a regular raster".
constexpr double kPaperStripesPerS = 3.5;

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
    std::deque<PlanEvent> events;
    std::optional<arm::Joints> arm_q;
    bool arm_moving = false;
    std::atomic<bool> finished{false};
    int exit_code = 0;

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

    // The scan in hand (task thread only).
    std::optional<ScanSequencer> seq;
    // Goal and request ids count up from this start's wall clock (us): a
    // restarted planner's ids never repeat the old one's (the arm would log
    // the same goal twice; the camera answers a request id it has answered
    // before with that old image).
    int64_t scan_id = 0, next_goal = wall_us(), next_request = wall_us();
    int last_goal_stripe = -1, last_retaken = 0, last_range_losses = 0;
    int scans_done = 0;
    double last_status_s = 0.0, pause_until_s = 0.0;
    ScanCpu cpu;
    CloudEvent last_cloud{};
    nlohmann::json summary;

    auto publish_scan = [&](double t) {
      stripe_scan_t m = scan_message_of(*seq, spec, scan_id, t);
      m.utime = wall_us();
      bus.publish(stripe::channels::kScan, m);
      last_status_s = t;
    };
    auto act = [&](const SequencerActions& a) {
      if (seq->range_losses() != last_range_losses) {
        last_range_losses = seq->range_losses();
        spdlog::warn(
            "scan {}: the range process has lost stripes it had ranged (restarted?): "
            "they will be taken again",
            scan_id);
      }
      if (seq->retaken() != last_retaken) {
        spdlog::warn("scan {}: going back for {} stripes without points", scan_id,
                     seq->retaken() - last_retaken);
        last_retaken = seq->retaken();
      }
      if (a.goal) {
        if (a.goal->stripe == last_goal_stripe)
          spdlog::warn("stripe {}: its goal sent again as goal {}", a.goal->stripe,
                       a.goal->goal_id);
        last_goal_stripe = a.goal->stripe;
        arm_goal_t g = goal_message_of(*a.goal, speed_mm_s);
        g.utime = wall_us();
        bus.publish(ephor::channels::kArmGoal, g);
      }
      if (a.capture) {
        stripe_capture_t c = capture_message_of(*a.capture, scan_id);
        c.utime = wall_us();
        bus.publish(stripe::channels::kCapture, c);
      }
      if (a.changed) publish_scan(now_s());
    };
    auto finish_scan = [&](double t) {
      const double per_stripe_us =
          cpu.extract_n > 0 && cpu.range_n > 0
              ? cpu.extract_cpu_us / cpu.extract_n + cpu.range_cpu_us / cpu.range_n
              : 0.0;
      summary = {
          {"system", "stripe"},
          {"scan_id", scan_id},
          {"state", to_string(seq->state())},
          {"reason", seq->reason()},
          {"robot_seed", robot_seed},
          {"calibration", calibration_path.empty() ? "drawing" : calibration_path},
          {"region_mm", {spec.x0_mm, spec.y0_mm, spec.x1_mm, spec.y1_mm}},
          {"step_mm", spec.step_mm},
          {"height_mm", spec.height_mm},
          {"stripes_planned", seq->planned()},
          {"stripes_captured", seq->captured()},
          {"stripes_skipped", seq->skipped()},
          {"stripes_retaken", seq->retaken()},
          {"range_losses", seq->range_losses()},
          {"stripes_missing_in_cloud", last_cloud.stripes_missing},
          {"cloud_points", seq->cloud_points()},
          {"cloud_path", last_cloud.path},
          {"elapsed_s", seq->elapsed_s(t)},
          {"motion_s", seq->motion_s()},
          {"stripes_per_s_scanned", seq->stripes_per_s()},
          {"paper_stripes_per_s", kPaperStripesPerS},
          {"processing_cpu_us_per_stripe", per_stripe_us},
          {"extract_cpu_us_per_stripe",
           cpu.extract_n > 0 ? cpu.extract_cpu_us / cpu.extract_n : 0.0},
          {"range_cpu_us_per_stripe", cpu.range_n > 0 ? cpu.range_cpu_us / cpu.range_n : 0.0}};
      if (seq->state() == ScanState::kDone) {
        spdlog::info(
            "scan {} done: {} of {} stripes ({} skipped, {} taken again), {} points in {:.1f} s: "
            "{:.2f} stripes/s "
            "scanned with the arm moving (paper: 3-4), arm moving {:.1f} s, processing {:.0f} us "
            "CPU a stripe",
            scan_id, seq->captured(), seq->planned(), seq->skipped(), seq->retaken(),
            seq->cloud_points(), seq->elapsed_s(t), seq->stripes_per_s(), seq->motion_s(),
            per_stripe_us);
      } else {
        spdlog::error("scan {} failed: {}", scan_id, seq->reason());
      }
      if (!summary_path.empty()) {
        std::ofstream out(summary_path);
        out << summary.dump(2) << "\n";
        if (!out) spdlog::error("could not write the summary to {}", summary_path);
      }
    };
    auto new_scan = [&](double t) -> bool {
      // Planned again from where the arm is (the same plan from the start
      // configuration; after a scan, from its last stripe).
      try {
        plan = plan_raster(spec, workcell, calibration.arm_model(), calibration.sensor, *arm_q);
      } catch (const PlanError& e) {
        spdlog::error("{}", e.what());
        return false;
      }
      scan_id = wall_us();
      seq.emplace(plan.goals, next_goal, next_request);
      last_goal_stripe = -1;
      last_retaken = last_range_losses = 0;
      cpu = ScanCpu{};
      last_cloud = CloudEvent{};
      spdlog::info(
          "scan {}: {} stripes {:g} mm apart over ({:g}, {:g}) - ({:g}, {:g}) mm, {:g} mm "
          "up; {}",
          scan_id, plan.goals.size(), spec.step_mm, spec.x0_mm, spec.y0_mm, spec.x1_mm, spec.y1_mm,
          spec.height_mm, calibration.measured);
      act(seq->start(t));
      publish_scan(t);
      return true;
    };

    auto job = [&] {
      const double t = now_s();
      std::deque<PlanEvent> batch;
      std::optional<arm::Joints> q;
      bool moving = false;
      {
        std::lock_guard<std::mutex> lock(mutex);
        batch.swap(events);
        q = arm_q;
        moving = arm_moving;
      }
      if (finished) return;
      if (!seq) {
        if (!q) return;  // no arm state yet (comm holds goals until it has one too)
        if (!new_scan(t)) {
          exit_code = 1;
          finished = true;
          return;
        }
      }
      for (const PlanEvent& e : batch) {
        if (const auto* d = std::get_if<DoneEvent>(&e);
            d && d->status == motion_done_t::STATUS_REJECTED)
          spdlog::warn("goal {} refused by the arm: {} (its stripe is skipped)", d->goal_id,
                       d->reason);
        apply_event(*seq, scan_id, e, t, cpu, &last_cloud, act);
      }
      if (moving) seq->on_arm_moving(t);
      act(seq->tick(t));
      if (t - last_status_s >= 1.0) publish_scan(t);
      if (seq->finished() && pause_until_s == 0.0) {
        finish_scan(t);
        next_goal = seq->next_goal_id();
        next_request = seq->next_request_id();
        ++scans_done;
        if (seq->state() == ScanState::kFailed) {
          exit_code = 1;
          finished = true;
        } else if (scans > 0 && scans_done >= scans) {
          finished = true;
        } else {
          pause_until_s = t + pause_s;
        }
      }
      if (pause_until_s > 0.0 && t >= pause_until_s && q) {
        pause_until_s = 0.0;
        arm_q = q;
        if (!new_scan(t)) {
          exit_code = 1;
          finished = true;
        }
      }
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
    return exit_code;
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
}
