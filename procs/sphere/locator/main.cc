// ephor-sphere-locator: the sphere's position every half second (paper 002,
// section 2 and appendix A). Collects the ranger's scan lines into windows
// [kW, (k+1)W) of the scan clock (WindowAssembler), and on each complete
// window runs Scan Line Extent or Sphere Fitting, as the paper wrote them or
// with the corrections beyond it (common/sphere SphereLocator).
//
//   subscribes  SPHERE_SCAN_LINE (sphere_scan_line_t)
//   publishes   SPHERE_ESTIMATE (sphere_estimate_t), one per complete
//               window: position at the algorithm's chosen time, velocity,
//               the counts and the CPU time, or "no estimate" and why
//   tasks       locate (triggered by a completed window)
//
// Bad lines (non-finite or backward times, arrays that disagree with their
// count, angles beyond +-pi, negative ranges, lines for a window already
// located) are counted and logged, never passed on.

#include <atomic>
#include <cmath>
#include <deque>
#include <limits>
#include <mutex>
#include <string>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include "common/lcm/bus.h"
#include "common/log/log.h"
#include "common/runtime/process_args.h"
#include "common/runtime/task_runtime.h"
#include "common/sphere/sphere_channels.h"
#include "common/sphere/sphere_locator.h"
#include "common/time/clock.h"
#include "ephor/sphere_estimate_t.hpp"
#include "ephor/sphere_scan_line_t.hpp"
#include "procs/sphere/locator/line_message.h"
#include "procs/sphere/locator/window_assembler.h"

using namespace ephor;
using namespace ephor::sphere;

int main(int argc, char** argv) {
  block_shutdown_signals();
  CLI::App app{"ephor-sphere-locator: the sphere's position from each half second of scan lines"};
  ProcessArgs args;
  add_process_flags(app, args, "locator");
  std::string algorithm = "sle", variant = "improved";
  double window_s = 0.5, background_m = 50.0, duration_s = 0.0;
  app.add_option("--algorithm", algorithm,
                 "sle (Scan Line Extent, default) or fit (Sphere Fitting)");
  app.add_option("--variant", variant,
                 "paper or improved (default: the corrections beyond the paper)");
  app.add_option("--window-s", window_s, "window length (s, default 0.5)")
      ->check(CLI::Range(0.05, 10.0));
  app.add_option("--background-m", background_m,
                 "returns at or beyond this range are background (m, default 50)")
      ->check(CLI::Range(0.1, 1e6));
  app.add_option("--duration", duration_s, "exit after this many seconds (0 = until signalled)")
      ->check(CLI::Range(0.0, 1e7));
  if (const auto exit_status = ephor::parse_flags(app, argc, argv)) return *exit_status;
  init_logging(args.name);

  LocatorConfig lc;
  try {
    lc.algorithm = parse_algorithm(algorithm);
    lc.variant = parse_variant(variant);
  } catch (const std::invalid_argument& e) {
    spdlog::error("{}", e.what());
    return 2;
  }
  lc.background_range_m = background_m;

  try {
    const SphereLocator locator(lc);
    WindowAssembler assembler(window_s);
    Bus bus(args.lcm_url, args.name);
    TaskRuntime runtime(bus, {args.name, args.host, !args.no_mlock});
    std::mutex mutex;
    std::deque<AssembledWindow> ready;
    std::atomic<int64_t> lines{0}, bad{0}, estimates{0}, no_estimates{0}, skipped{0},
        missing_lines{0};

    bus.subscribe<sphere_scan_line_t>(channels::kScanLine, [&](const sphere_scan_line_t& m) {
      std::string why;
      bool complete = false;
      {
        std::lock_guard<std::mutex> lock(mutex);
        const int64_t restarts_before = assembler.restarts();
        why = assembler.add(line_message_of(m));
        if (assembler.restarts() != restarts_before) {
          spdlog::warn(
              "SPHERE_SCAN_LINE from {}: scan clock and line counter went back (line {} at {:.3f} "
              "s): the ranger restarted; assembling its windows afresh",
              m.header.sender, m.line, m.t_s.empty() ? 0.0 : m.t_s.front());
        }
        for (AssembledWindow& w : assembler.take_complete()) {
          ready.push_back(std::move(w));
          complete = true;
        }
        // Newest data first (NASREM): if the task fell behind by more than a
        // window, the oldest windows are dropped, counted.
        while (ready.size() > 2) {
          ready.pop_front();
          ++skipped;
        }
      }
      ++lines;
      if (!why.empty()) {
        const int64_t n = ++bad;
        if (n <= 10 || n % 100 == 0) {
          spdlog::warn("SPHERE_SCAN_LINE from {} refused: {} ({} refused so far)", m.header.sender,
                       why, n);
        }
      }
      if (complete) runtime.trigger("locate");
    });

    runtime.add_triggered("locate", std::chrono::milliseconds(100), [&] {
      for (;;) {
        AssembledWindow w;
        {
          std::lock_guard<std::mutex> lock(mutex);
          if (ready.empty()) return;
          w = std::move(ready.front());
          ready.pop_front();
        }
        double cpu_us = 0.0;
        const Estimate e = locator.locate(w.window, &cpu_us);
        sphere_estimate_t m = estimate_message_of(e, w, lc);
        m.utime = wall_us();
        m.cpu_us = static_cast<float>(cpu_us);
        bus.publish(channels::kEstimate, m);
        missing_lines += w.lines_missing;
        if (e.ok) {
          ++estimates;
          spdlog::debug("window {}: ({:.3f}, {:.3f}, {:.3f}) m at {:.3f} s, {} lines, {:.0f} us",
                        w.index, e.position_m.x(), e.position_m.y(), e.position_m.z(), e.t_s,
                        e.lines, cpu_us);
        } else {
          const int64_t n = ++no_estimates;
          if (n <= 10 || n % 100 == 0) {
            spdlog::info("window {}: no estimate: {} ({} lines received, {} missing)", w.index,
                         e.reason, w.lines_received, w.lines_missing);
          }
        }
      }
    });

    runtime.start();
    spdlog::info("ready: {} ({}), windows of {:.2f} s, background at >= {:.0f} m",
                 to_string(lc.algorithm), to_string(lc.variant), window_s, background_m);
    wait_for_shutdown_signal(duration_s);
    runtime.stop();
    spdlog::info(
        "summary: {} lines, {} refused, {} estimates, {} no estimate, {} windows skipped, {} "
        "lines missing",
        lines.load(), bad.load(), estimates.load(), no_estimates.load(), skipped.load(),
        missing_lines.load());
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
  return 0;
}
