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
// Time: the scan clock t_s is seconds since start-up (CLOCK_MONOTONIC); a
// message's utime is the wall clock at start plus t_s.

#include <atomic>
#include <cmath>
#include <fstream>
#include <limits>
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

namespace {

using namespace ephor;
using namespace ephor::sphere;

sphere_scan_line_t to_message(const RangerLine& l, double window_s, int64_t utime) {
  sphere_scan_line_t m{};
  m.utime = utime;
  m.line = l.line.id;
  m.window = l.window;
  m.window_s = window_s;
  m.last_in_window = l.last_in_window;
  m.half_extent_deg = static_cast<float>(l.half_extent_deg);
  m.num_pulses = static_cast<int32_t>(l.line.pulses.size());
  for (const Pulse& p : l.line.pulses) {
    m.t_s.push_back(p.t_s);
    m.azimuth_rad.push_back(p.azimuth_rad);
    m.elevation_rad.push_back(p.elevation_rad);
    m.range_m.push_back(p.range_m);
  }
  return m;
}

void fill_truth(sphere_truth_t& m, const RangerTruth& t) {
  m.t_s = t.t_s;
  m.approach = t.approach;
  for (int i = 0; i < 3; ++i) {
    m.position_m[i] = t.position_m[i];
    m.velocity_m_s[i] = t.velocity_m_s[i];
    m.chaser_velocity_m_s[i] = t.chaser_velocity_m_s[i];
    m.target_velocity_m_s[i] = t.target_velocity_m_s[i];
  }
  m.half_extent_deg = static_cast<float>(t.half_extent_deg);
}

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
    std::mutex mutex;
    std::atomic<int64_t> lines_published{0}, commands{0}, commands_refused{0};
    std::atomic<bool> finished{false};
    size_t verdicts_published = 0;

    bus.subscribe<sphere_guidance_t>(channels::kGuidance, [&](const sphere_guidance_t& m) {
      const Eigen::Vector3d v(m.chaser_velocity_m_s[0], m.chaser_velocity_m_s[1],
                              m.chaser_velocity_m_s[2]);
      bool ok;
      {
        std::lock_guard<std::mutex> lock(mutex);
        ok = world.command(m.apply_t_s, v);
      }
      if (!ok) {
        const int64_t n = ++commands_refused;
        if (n <= 10 || n % 100 == 0) {
          spdlog::warn("SPHERE_GUIDANCE from {} ignored: non-finite time or velocity ({} so far)",
                       m.header.sender, n);
        }
        return;
      }
      ++commands;
    });

    const int64_t wall0_us = wall_us();
    const int64_t mono0_ns = mono_ns();
    auto now_s = [&] { return static_cast<double>(mono_ns() - mono0_ns) * 1e-9; };
    auto utime_of = [&](double t_s) { return wall0_us + std::llround(t_s * 1e6); };

    runtime.add_periodic("scan", std::chrono::milliseconds(5), [&] {
      std::vector<RangerLine> lines;
      std::vector<sphere_truth_t> verdicts;
      {
        std::lock_guard<std::mutex> lock(mutex);
        lines = world.advance_to(now_s());
        while (verdicts_published < world.verdicts().size()) {
          const CaptureVerdict& v = world.verdicts()[verdicts_published];
          sphere_truth_t m{};
          // The state at the verdict's moment (the window it fell in is the
          // current one unless the next sphere has already come).
          RangerTruth t = world.truth_at(v.t_s);
          t.position_m = v.position_m;
          t.velocity_m_s = v.velocity_m_s;
          t.approach = static_cast<int>(verdicts_published);
          fill_truth(m, t);
          m.utime = utime_of(v.t_s);
          m.phase = v.captured ? sphere_truth_t::PHASE_CAPTURED : sphere_truth_t::PHASE_MISSED;
          m.capture_t_s = v.t_s;
          m.capture_speed_m_s = v.speed_m_s;
          m.capture_offset_m = v.offset_m;
          m.verdict = v.text;
          spdlog::info("approach {}: {}", verdicts_published, v.text);
          verdicts.push_back(m);
          ++verdicts_published;
        }
        if (world.finished()) finished = true;
      }
      for (const RangerLine& l : lines) {
        sphere_scan_line_t m = to_message(l, window_s, utime_of(l.ready_t_s));
        bus.publish(channels::kScanLine, m);
        ++lines_published;
      }
      for (sphere_truth_t& m : verdicts) bus.publish(channels::kTruth, m);
    });

    runtime.add_periodic("truth", std::chrono::milliseconds(50), [&] {
      sphere_truth_t m{};
      {
        std::lock_guard<std::mutex> lock(mutex);
        if (world.finished()) return;
        const double t = now_s();
        if (static_cast<double>(world.windows_started()) * window_s <= t) return;  // scan lags
        fill_truth(m, world.truth_at(t));
        m.utime = utime_of(t);
      }
      m.phase = sphere_truth_t::PHASE_APPROACH;
      m.capture_t_s = std::numeric_limits<double>::quiet_NaN();
      bus.publish(channels::kTruth, m);
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
    while (!finished && mono_ns() < t_end) {
      if (wait_for_shutdown_signal(0.05) != 0) break;
    }
    runtime.stop();
    std::lock_guard<std::mutex> lock(mutex);
    int captured = 0;
    for (const CaptureVerdict& v : world.verdicts()) captured += v.captured ? 1 : 0;
    std::string last = world.verdicts().empty() ? "no verdict (stopped before the capture distance)"
                                                : world.verdicts().back().text;
    spdlog::info(
        "summary: {} of {} approaches captured; last: {}; {} windows, {} lines, {} guidance "
        "commands, {} refused",
        captured, world.verdicts().size(), last, world.windows_started(), lines_published.load(),
        commands.load(), commands_refused.load());
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
                                {"lines", lines_published.load()},
                                {"guidance_commands", commands.load()},
                                {"commands_refused", commands_refused.load()}};
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
