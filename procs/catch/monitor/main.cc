// ephor-catch-monitor: watches a catching run and says how it is doing: a
// status line every few seconds (balls, catches, rates, accuracy) and, on
// exit, a JSON summary (--summary FILE) scored against the simulator's
// ground truth (common/catch/summary/catch_summary.h). Only listens.

#include <fstream>
#include <mutex>
#include <string>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include "common/catch/catch_channels.h"
#include "common/catch/summary/catch_summary.h"
#include "common/lcm/bus.h"
#include "common/lcm/channels.h"
#include "common/log/json_text.h"
#include "common/log/log.h"
#include "common/runtime/channels.h"
#include "common/runtime/process_args.h"
#include "common/time/clock.h"
#include "procs/catch/monitor/catch_monitor_feed.h"

int main(int argc, char** argv) {
  using namespace ephor;
  using namespace ephor::catching;
  block_shutdown_signals();
  CLI::App app{"ephor-catch-monitor: status line and run summary of the catching system"};
  ProcessArgs args;
  add_process_flags(app, args, "monitor");
  std::string summary_path;
  int64_t seed = 0;
  double every_s = 5.0;
  app.add_option("--summary", summary_path, "write the run summary (JSON) here on exit");
  app.add_option("--seed", seed, "the run's seed, written into the summary");
  app.add_option("--status-every", every_s, "seconds between status lines (0 = none)")
      ->check(CLI::NonNegativeNumber);
  if (const auto exit_status = ephor::parse_flags(app, argc, argv)) return *exit_status;
  init_logging(args.name);

  try {
    Bus bus(args.lcm_url, args.name);
    std::mutex mutex;
    CatchSummary summary(seed);
    CatchMonitorFeed feed(summary);

    bus.subscribe<catch_truth_t>(catching::channels::kTruth, [&](const catch_truth_t& m) {
      std::lock_guard<std::mutex> lock(mutex);
      if (const auto line = feed.on_truth(m)) spdlog::info("{}", *line);
    });
    bus.subscribe<catch_world_t>(catching::channels::kWorld, [&](const catch_world_t& m) {
      std::lock_guard<std::mutex> lock(mutex);
      feed.on_world(m);
    });
    bus.subscribe<catch_board_pose_t>(catching::channels::kBoardPose,
                                      [&](const catch_board_pose_t& m) {
                                        std::lock_guard<std::mutex> lock(mutex);
                                        feed.on_board_pose(m);
                                      });
    bus.subscribe<sched_status_t>(ephor::channels::kSchedStatus, [&](const sched_status_t& m) {
      std::lock_guard<std::mutex> lock(mutex);
      feed.on_sched_status(m);
    });
    bus.start();

    while (wait_for_shutdown_signal(every_s > 0 ? every_s : 3600.0) == 0) {
      if (every_s <= 0) continue;
      std::lock_guard<std::mutex> lock(mutex);
      spdlog::info("{}", summary.status_line());
    }
    bus.stop();
    std::lock_guard<std::mutex> lock(mutex);
    spdlog::info("final: {}", summary.status_line());
    if (!summary_path.empty()) {
      std::ofstream out(summary_path);
      if (!out) throw std::runtime_error("cannot write summary to " + summary_path);
      out << json_text(summary.to_json(), 2) << "\n";
      spdlog::info("summary written to {}", summary_path);
    }
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
  return 0;
}
