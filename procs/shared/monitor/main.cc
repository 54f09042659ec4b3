// ephor-monitor: watches a running system and says how it is doing: a status
// line every few seconds (sheep on the field, saves, escapes, rates,
// latency) and, on exit, a JSON summary (--summary FILE) scored against the
// simulator's ground truth. Not a real-time task: it only listens.

#include <fstream>
#include <mutex>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include "common/lcm/bus.h"
#include "common/lcm/channels.h"
#include "common/log/json_text.h"
#include "common/log/log.h"
#include "common/runtime/channels.h"
#include "common/runtime/process_args.h"
#include "common/time/clock.h"
#include "procs/shared/monitor/monitor_feed.h"
#include "procs/shared/monitor/run_monitor.h"

int main(int argc, char** argv) {
  using namespace ephor;
  block_shutdown_signals();
  CLI::App app{"ephor-monitor: status line and run summary"};
  ProcessArgs args;
  add_process_flags(app, args, "monitor");
  std::string summary_path;
  std::string scenario = "shepherd";
  double every_s = 5.0;
  app.add_option("--summary", summary_path, "write the run summary (JSON) here on exit");
  app.add_option("--scenario", scenario, "scenario name written into the summary");
  app.add_option("--status-every", every_s, "seconds between status lines (0 = none)")
      ->check(CLI::NonNegativeNumber);
  if (const auto exit_status = ephor::parse_flags(app, argc, argv)) return *exit_status;
  init_logging(args.name);

  try {
    Bus bus(args.lcm_url, args.name);
    std::mutex mutex;
    monitor::RunMonitor mon(scenario);
    monitor::MonitorFeed feed(mon);
    bus.subscribe<shepherd_ground_truth_t>(channels::kGroundTruth,
                                           [&](const shepherd_ground_truth_t& m) {
                                             std::lock_guard<std::mutex> lock(mutex);
                                             feed.on_truth(m);
                                           });
    bus.subscribe<shepherd_blobs_t>(channels::kBlobs, [&](const shepherd_blobs_t& m) {
      std::lock_guard<std::mutex> lock(mutex);
      feed.on_blobs(m, wall_us());
    });
    bus.subscribe<shepherd_objects_t>(channels::kObjects, [&](const shepherd_objects_t& m) {
      std::lock_guard<std::mutex> lock(mutex);
      feed.on_objects(m, wall_us());
    });
    bus.subscribe<arm_goal_t>(channels::kArmGoal, [&](const arm_goal_t& m) {
      std::lock_guard<std::mutex> lock(mutex);
      feed.on_arm_goal(m);
    });
    bus.subscribe<arm_cmd_t>(channels::kArmCmd, [&](const arm_cmd_t& m) {
      std::lock_guard<std::mutex> lock(mutex);
      feed.on_arm_cmd(m);
    });
    bus.subscribe<sched_status_t>(channels::kSchedStatus, [&](const sched_status_t& m) {
      std::lock_guard<std::mutex> lock(mutex);
      feed.on_sched_status(m);
    });
    bus.start();

    while (wait_for_shutdown_signal(every_s > 0 ? every_s : 3600.0) == 0) {
      if (every_s <= 0) continue;
      std::lock_guard<std::mutex> lock(mutex);
      for (const auto& e : mon.take_events()) spdlog::info("{}", e);
      spdlog::info("{}", mon.status_line(wall_us()));
    }
    bus.stop();
    std::lock_guard<std::mutex> lock(mutex);
    const auto summary = mon.summary(wall_us());
    for (const auto& e : mon.take_events()) spdlog::info("{}", e);
    spdlog::info("final: {}", mon.status_line(wall_us()));
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
