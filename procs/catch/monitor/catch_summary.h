#pragma once
// CatchSummary: scores a catching run against the simulator's ground truth
// (ephor-catch-monitor writes it as the --summary JSON of
// `tools/ephor run deploy/catch.pbtxt --headless --balls N --summary F`).
//
// Fed with plain values (the monitor converts the LCM messages): the truth
// of every frame, every world-model output, the camera pose from the
// circles, the schedulers' status. Times in us (wall clock), lengths in mm.

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "common/runtime/rolling_stats.h"

namespace ephor::catching {

struct BallOutcome {
  int ball = 0;
  bool caught = false;
  bool oracle_reachable = false;
  std::string reason;
};

class CatchSummary {
 public:
  explicit CatchSummary(int64_t seed);

  // One frame of ground truth: the ball's centre on the board (B) and the
  // results so far. Outcomes are taken when last_ball changes.
  void on_truth(int64_t utime, bool rolling, const Eigen::Vector2d& ball_b_mm, int last_ball,
                bool last_caught, bool last_oracle_reachable, const std::string& last_reason,
                const Eigen::Isometry3d& true_board_to_camera);
  // One world-model output: capture time, when it was published, and the
  // filtered ball position on the board when tracking.
  void on_world(int64_t capture_utime, double latency_ms,
                const std::optional<Eigen::Vector2d>& position_b_mm);
  void on_board_pose(const Eigen::Isometry3d& board_to_camera);
  void on_sched_status(const std::string& host, bool rt, int64_t deadline_misses);
  // One task's execution time (thread CPU time, us) as its scheduler reports
  // it: the paper's Table 1 per process.
  void on_task(const std::string& process, const std::string& task, double exec_p50_us,
               double exec_p99_us, int64_t jobs, int64_t deadline_misses);

  int balls() const { return static_cast<int>(outcomes_.size()); }
  int caught() const;
  std::string status_line() const;
  nlohmann::json to_json() const;

 private:
  int64_t seed_;
  std::vector<BallOutcome> outcomes_;
  int last_ball_ = -1;
  // Truth of the newest frames by capture time, to score world outputs.
  std::map<int64_t, Eigen::Vector2d> truth_by_utime_;
  std::optional<Eigen::Isometry3d> true_pose_, measured_pose_;
  RollingStats update_ms_{100000}, throughput_ms_{100000}, position_error_mm_{100000};
  int64_t last_world_utime_ = 0;
  int64_t world_outputs_ = 0;
  std::map<std::string, std::pair<bool, int64_t>> hosts_;
  std::map<std::string, nlohmann::json> tasks_;  // "process/task" -> newest figures
};

}  // namespace ephor::catching
