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
#include "common/log/log.h"
#include "common/runtime/channels.h"
#include "common/runtime/process_args.h"
#include "common/time/clock.h"
#include "ephor/catch_board_pose_t.hpp"
#include "ephor/catch_truth_t.hpp"
#include "ephor/catch_world_t.hpp"
#include "ephor/sched_status_t.hpp"

namespace {

Eigen::Isometry3d pose_of(const double r[9], const double t[3]) {
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) p.linear()(i, j) = r[3 * i + j];
    p.translation()[i] = t[i];
  }
  return p;
}

}  // namespace

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
    int last_logged = -1;

    bus.subscribe<catch_truth_t>(catching::channels::kTruth, [&](const catch_truth_t& m) {
      std::lock_guard<std::mutex> lock(mutex);
      summary.on_truth(m.utime, m.phase == catch_truth_t::PHASE_ROLLING,
                       Eigen::Vector2d(m.ball_b_mm[0], m.ball_b_mm[1]), m.last_ball, m.last_caught,
                       m.last_oracle_reachable, m.last_reason,
                       pose_of(m.board_to_camera_r, m.board_to_camera_t_mm));
      summary.on_ball_truth(m.utime, m.ball, m.phase == catch_truth_t::PHASE_ROLLING,
                            Eigen::Vector2d(m.ball_b_mm[0], m.ball_b_mm[1]), m.exit_x_b_mm,
                            m.exit_utime);
      if (m.last_ball >= 0 && m.last_ball != last_logged) {
        last_logged = m.last_ball;
        spdlog::info("ball {}: {}{}", m.last_ball, m.last_caught ? "" : "missed: ", m.last_reason);
      }
    });
    bus.subscribe<catch_world_t>(catching::channels::kWorld, [&](const catch_world_t& m) {
      std::optional<Eigen::Vector2d> p;
      if (m.status == catch_world_t::STATUS_TRACKING)
        p = Eigen::Vector2d(m.position_b_mm[0], m.position_b_mm[1]);
      std::lock_guard<std::mutex> lock(mutex);
      summary.on_world(m.utime, m.latency_ms, p);
      summary.on_prediction(m.utime, m.status == catch_world_t::STATUS_TRACKING,
                            m.has_prediction != 0, m.exit_x_b_mm, p);
    });
    bus.subscribe<catch_board_pose_t>(catching::channels::kBoardPose,
                                      [&](const catch_board_pose_t& m) {
                                        if (!m.valid) return;
                                        std::lock_guard<std::mutex> lock(mutex);
                                        summary.on_board_pose(pose_of(m.r, m.t_mm));
                                      });
    bus.subscribe<sched_status_t>(ephor::channels::kSchedStatus, [&](const sched_status_t& m) {
      int64_t misses = 0;
      for (const auto& t : m.tasks) misses += t.deadline_misses;
      std::lock_guard<std::mutex> lock(mutex);
      summary.on_sched_status(m.host, m.rt != 0, misses);
      for (const auto& t : m.tasks)
        summary.on_task(t.process, t.task, t.exec_p50_us, t.exec_p99_us, t.jobs, t.deadline_misses);
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
      out << summary.to_json().dump(2) << "\n";
      spdlog::info("summary written to {}", summary_path);
    }
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
  return 0;
}
