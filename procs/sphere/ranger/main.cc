// ephor-sphere-ranger: the chaser's scanning laser range finder and the
// simulated world of the sphere system (paper 002, sections 3-4; issue 15).
// Every half-second window gets a fresh raster (1000 deg/s in azimuth,
// 10 deg/s in elevation, 10 kHz pulses, the frame 105 % of what the sphere
// needs during the window, upper left first), ranges ray-cast to the moving
// 16 cm sphere with section 3's noise (2 cm in range, 0.78 mrad per encoder),
// and optionally a far background (>= 50 m) over the lower part of the
// frame. Each scan line is published when its last pulse is measured. The
// sphere drifts at constant velocity (Table 1's speeds for the start
// distance unless --drift-m-s); the chaser flies ephor-sphere-guidance's
// commanded velocity, changing it only at window boundaries and by at most
// --accel-m-s2 * window (RelativeMotion).
//
// When the sphere's centre reaches the capture distance along the boresight
// it judges the capture (below 2 cm/s, within 2 cm of the axis), logs the
// verdict and, after --approaches approaches, exits 0 (the manifest's
// ends_run ends the run). --max-s gives an approach up ("not captured").
//
//   subscribes  SPHERE_GUIDANCE (sphere_guidance_t): the chaser's velocity
//   publishes   SPHERE_SCAN_LINE (sphere_scan_line_t), one per scan line
//               SPHERE_TRUTH (sphere_truth_t), 20 Hz and at each verdict
//   tasks       scan (periodic 5 ms), truth (periodic 50 ms)
//
// The handler and the tasks' work are RangerProcess (ranger_messages.h; the
// fuzz target sphere_ranger runs them); this file is the wiring.
//
// Time: the scan clock t_s is seconds since start-up (CLOCK_MONOTONIC); a
// message's utime is the wall clock at start plus t_s.

#include <cmath>
#include <fstream>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "common/lcm/bus.h"
#include "common/log/log.h"
#include "common/runtime/process_args.h"
#include "common/runtime/task_runtime.h"
#include "common/sphere/sphere_channels.h"
#include "common/sphere/world/ranger_world.h"
#include "common/time/clock.h"
#include "ephor/sphere_guidance_t.hpp"
#include "ephor/sphere_scan_line_t.hpp"
#include "ephor/sphere_truth_t.hpp"
#include "procs/sphere/ranger/ranger_messages.h"

namespace {

using namespace ephor;
using namespace ephor::sphere;

bool parse_vector(const std::vector<double>& v, Eigen::Vector3d& out) {
  if (v.size() != 3) return false;
  out = Eigen::Vector3d(v[0], v[1], v[2]);
  return out.allFinite();
}

}  // namespace

int main(int argc, char** argv) {
  block_shutdown_signals();
  CLI::App app{"ephor-sphere-ranger: the chaser's scanning laser range finder and the sphere"};
  ProcessArgs args;
  add_process_flags(app, args, "ranger");
  RangerWorldConfig config;
  double start_m = 20.0, duration_s = 0.0;
  std::vector<double> drift, offset;
  bool background = false;
  int64_t seed = 1;
  app.add_option("--seed", seed, "random seed of the range noise (default 1)");
  app.add_option("--start-m", start_m, "the sphere's distance along the boresight at start (m)")
      ->check(CLI::Range(1.05, 5000.0));
  app.add_option("--start-offset-m", offset, "its offset across the boresight at start: x,y (m)")
      ->delimiter(',')
      ->expected(2);
  app.add_option("--drift-m-s", drift,
                 "the sphere's drift x,y,z (m/s, sensor frame; default Table 1's speeds at the "
                 "start distance: up, right and 3.6 cm/s toward the sensor)")
      ->delimiter(',')
      ->expected(3);
  app.add_option("--accel-m-s2", config.motion.max_accel_m_s2,
                 "the chaser's acceleration limit (m/s^2, default 0.05)")
      ->check(CLI::Range(0.0, 10.0));
  app.add_option("--window-s", config.motion.window_s,
                 "measurement window: a fresh raster and a possible burn each (default 0.5)")
      ->check(CLI::Range(0.05, 10.0));
  app.add_option("--range-sigma-m", config.noise.range_sigma_m, "range noise (default 0.02)")
      ->check(CLI::Range(0.0, 10.0));
  app.add_option("--angle-sigma-rad", config.noise.angle_sigma_rad,
                 "noise of each encoder angle (default 0.00078)")
      ->check(CLI::Range(0.0, 0.1));
  app.add_flag(
      "--background", background,
      "a far wall (60 m) behind the lower part of the frame, for the locator to threshold");
  app.add_option("--background-below-deg", config.background.below_elevation_deg,
                 "the wall fills pulses below this elevation (deg, default 0)")
      ->check(CLI::Range(-90.0, 90.0));
  app.add_option("--capture-m", config.capture.capture_distance_m,
                 "capture distance along the boresight (m, default 1)")
      ->check(CLI::Range(0.2, 100.0));
  app.add_option("--capture-speed-m-s", config.capture.max_speed_m_s,
                 "largest relative speed at capture (default 0.02)")
      ->check(CLI::Range(1e-6, 10.0));
  app.add_option("--capture-offset-m", config.capture.max_offset_m,
                 "largest offset from the capture axis (default 0.02)")
      ->check(CLI::Range(1e-6, 10.0));
  app.add_option("--max-s", config.max_s, "give an approach up after this long (s, 0 = never)")
      ->check(CLI::Range(0.0, 1e6));
  app.add_option("--approaches", config.approaches,
                 "approaches, then exit 0 (0 = until stopped; each after the first starts a "
                 "fresh sphere at the start distance)")
      ->check(CLI::Range(0, 1000000));
  std::string summary_path;
  app.add_option("--summary", summary_path, "write a JSON summary of the approaches here at exit");
  app.add_option("--duration", duration_s, "exit after this many seconds (0 = until done)")
      ->check(CLI::Range(0.0, 1e7));
  if (const auto exit_status = ephor::parse_flags(app, argc, argv)) return *exit_status;
  init_logging(args.name);

  config.seed = static_cast<uint64_t>(seed);
  config.background.enabled = background;
  config.motion.start_position_m = Eigen::Vector3d(0.0, 0.0, start_m);
  if (!offset.empty()) {
    if (offset.size() != 2 || !std::isfinite(offset[0]) || !std::isfinite(offset[1])) {
      spdlog::error("--start-offset-m wants two finite numbers x,y");
      return 2;
    }
    config.motion.start_position_m.head<2>() = Eigen::Vector2d(offset[0], offset[1]);
  }
  config.motion.target_velocity_m_s = RelativeMotionConfig::table1_drift(start_m);
  if (!drift.empty() && !parse_vector(drift, config.motion.target_velocity_m_s)) {
    spdlog::error("--drift-m-s wants three finite numbers x,y,z");
    return 2;
  }

  std::optional<RangerWorld> made;
  try {
    made.emplace(config);
  } catch (const std::invalid_argument& e) {
    spdlog::error("{}", e.what());
    return 2;
  }
  RangerWorld& world = *made;

  try {
    const double window_s = config.motion.window_s;
    Bus bus(args.lcm_url, args.name);
    TaskRuntime runtime(bus, {args.name, args.host, !args.no_mlock});
    const int64_t wall0_us = wall_us();
    const int64_t mono0_ns = mono_ns();
    RangerProcess ranger(world, wall0_us);
    auto now_s = [&] { return static_cast<double>(mono_ns() - mono0_ns) * 1e-9; };

    bus.subscribe<sphere_guidance_t>(
        channels::kGuidance, [&ranger](const sphere_guidance_t& m) { ranger.on_guidance(m); });

    runtime.add_periodic("scan", std::chrono::milliseconds(5), [&] {
      RangerProcess::Scan out = ranger.scan(now_s());
      for (sphere_scan_line_t& m : out.lines) bus.publish(channels::kScanLine, m);
      for (sphere_truth_t& m : out.verdicts) bus.publish(channels::kTruth, m);
    });

    runtime.add_periodic("truth", std::chrono::milliseconds(50), [&] {
      if (std::optional<sphere_truth_t> m = ranger.truth(now_s()))
        bus.publish(channels::kTruth, *m);
    });

    runtime.start();
    const Eigen::Vector3d& d = config.motion.target_velocity_m_s;
    spdlog::info(
        "running: seed {}, sphere at {:.2f} m drifting ({:.3f}, {:.3f}, {:.3f}) m/s, chaser "
        "limit {:.3f} m/s^2, windows of {:.2f} s, {} approach(es){}",
        seed, start_m, d.x(), d.y(), d.z(), config.motion.max_accel_m_s2, window_s,
        config.approaches == 0 ? std::string("endless") : std::to_string(config.approaches),
        background ? ", far background" : "");
    const int64_t t_end =
        duration_s > 0 ? mono_ns() + static_cast<int64_t>(duration_s * 1e9) : INT64_MAX;
    while (!ranger.finished() && mono_ns() < t_end) {
      if (wait_for_shutdown_signal(0.05) != 0) break;
    }
    runtime.stop();
    std::lock_guard<std::mutex> lock(ranger.mutex());
    int captured = 0;
    for (const CaptureVerdict& v : world.verdicts()) captured += v.captured ? 1 : 0;
    std::string last = world.verdicts().empty() ? "no verdict (stopped before the capture distance)"
                                                : world.verdicts().back().text;
    spdlog::info(
        "summary: {} of {} approaches captured; last: {}; {} windows, {} lines, {} guidance "
        "commands, {} refused",
        captured, world.verdicts().size(), last, world.windows_started(), ranger.lines_published(),
        ranger.commands(), ranger.commands_refused());
    if (!summary_path.empty()) {
      nlohmann::json runs = nlohmann::json::array();
      for (const CaptureVerdict& v : world.verdicts()) {
        runs.push_back({{"captured", v.captured},
                        {"t_s", v.t_s},
                        {"speed_m_s", v.speed_m_s},
                        {"offset_m", v.offset_m},
                        {"verdict", v.text}});
      }
      const nlohmann::json j = {{"scenario", "sphere"},
                                {"seed", seed},
                                {"start_m", start_m},
                                {"captured", captured},
                                {"approaches", runs},
                                {"windows", world.windows_started()},
                                {"lines", ranger.lines_published()},
                                {"guidance_commands", ranger.commands()},
                                {"commands_refused", ranger.commands_refused()}};
      std::ofstream out(summary_path);
      out << j.dump(2) << "\n";
      if (!out) spdlog::error("cannot write the summary to {}", summary_path);
    }
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
  return 0;
}
