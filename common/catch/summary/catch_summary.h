#pragma once
// CatchSummary: scores a catching run against the simulator's ground truth
// (ephor-catch-monitor writes it as the --summary JSON of
// `tools/ephor run deploy/catch.pbtxt --headless --balls N --summary F`).
//
// Fed with plain values (the monitor converts the LCM messages): the truth
// of every frame, every world-model output, the camera pose from the
// circles, the schedulers' status. Times in us (wall clock), lengths in mm.

#include <cmath>
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
  // Why a missed ball was missed, from the world model's predictions of its
  // exit against the simulator's (see classify_miss): "not tracked",
  // "wrong place", "prediction late" or "arm late"; "" when caught.
  std::string kind;
  double prediction_error_mm = std::nan("");  // the last prediction's exit x error, B
  double lead_s = std::nan("");              // how long before the true exit the prediction settled
  double first_tracked_y_mm = std::nan("");  // where on the board the track began (truth, B)
  // Where the world model's tracked position first strayed by more than
  // 50 mm from the truth (truth y, B; NaN = never), and the largest error.
  double strayed_at_y_mm = std::nan("");
  double max_track_error_mm = std::nan("");
};

// What the monitor saw of one ball while it rolled: the simulator's exit
// (simulated ahead at release) and the world model's predictions of it.
struct BallTrack {
  int ball = -1;
  double true_exit_x_b_mm = std::nan("");
  int64_t true_exit_utime = 0;
  double first_tracked_y_mm = std::nan("");
  double strayed_at_y_mm = std::nan("");
  double max_track_error_mm = std::nan("");
  // (capture utime, predicted exit x in B) of every output with a prediction
  // made while the ball rolled.
  std::vector<std::pair<int64_t, double>> predictions;
};

// The loss classes of a missed ball, judged on the exit x (B, mm) within
// tolerance_mm (the cup's: inner radius minus the ball's radius):
//   not tracked      no prediction while the ball rolled
//   wrong place      the last prediction before the exit was off by more
//   prediction late  it settled (every later prediction within tolerance)
//                    less than late_lead_s before the exit: too late for
//                    the arm to get there from the ready point
//   arm late         it settled earlier: the cup could have been there
// Fills kind, prediction_error_mm, lead_s, first_tracked_y_mm of `outcome`.
void classify_miss(const BallTrack& track, double tolerance_mm, double late_lead_s,
                   BallOutcome& outcome);

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
  // The ball of one truth frame (index, on the board or not, its true exit)
  // and the world model's prediction of the same capture time (has_prediction
  // false when none): feeds the per-ball miss classification.
  void on_ball_truth(int64_t utime, int ball, bool rolling, const Eigen::Vector2d& ball_b_mm,
                     double true_exit_x_b_mm, int64_t true_exit_utime);
  // position_b_mm: the tracked ball (when tracking), scored against the truth.
  void on_prediction(int64_t capture_utime, bool tracking, bool has_prediction, double exit_x_b_mm,
                     const std::optional<Eigen::Vector2d>& position_b_mm = std::nullopt);
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
  std::map<int, BallTrack> tracks_;                                           // by truth ball index
  std::map<int64_t, std::pair<int, Eigen::Vector2d>> rolling_ball_by_utime_;  // -> (ball, B)
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
