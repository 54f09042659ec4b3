#include "common/catch/summary/catch_summary.h"

#include <cmath>

#include <fmt/format.h>

#include "common/runtime/counts.h"

namespace ephor::catching {

namespace {

nlohmann::json percentiles(const RollingStats& s) {
  if (s.empty()) return {{"p50", nullptr}, {"p99", nullptr}, {"n", 0}};
  return {{"p50", s.percentile(50)}, {"p99", s.percentile(99)}, {"max", s.max()}, {"n", s.size()}};
}

// The cup's tolerance: inner radius 50 mm minus the ball's radius 20 mm.
constexpr double kToleranceMm = 30.0;
// Below this lead the arm cannot cover the ~100-200 mm of a typical miss
// from rest (1 rad/s, 2 rad/s^2 on joints 1-3: ~0.5 s for 100 mm).
constexpr double kLateLeadS = 0.5;

}  // namespace

void classify_miss(const BallTrack& track, double tolerance_mm, double late_lead_s,
                   BallOutcome& outcome) {
  outcome.first_tracked_y_mm = track.first_tracked_y_mm;
  outcome.strayed_at_y_mm = track.strayed_at_y_mm;
  outcome.max_track_error_mm = track.max_track_error_mm;
  if (track.predictions.empty() || !std::isfinite(track.true_exit_x_b_mm)) {
    outcome.kind = "not tracked";
    return;
  }
  const double last_error = std::abs(track.predictions.back().second - track.true_exit_x_b_mm);
  outcome.prediction_error_mm = last_error;
  if (last_error > tolerance_mm) {
    outcome.kind = "wrong place";
    return;
  }
  // The first prediction from which every later one is within tolerance.
  int64_t settled = track.predictions.back().first;
  for (auto it = track.predictions.rbegin(); it != track.predictions.rend(); ++it) {
    if (std::abs(it->second - track.true_exit_x_b_mm) > tolerance_mm) break;
    settled = it->first;
  }
  outcome.lead_s = static_cast<double>(track.true_exit_utime - settled) / 1e6;
  outcome.kind = outcome.lead_s < late_lead_s ? "prediction late" : "arm late";
}

CatchSummary::CatchSummary(int64_t seed) : seed_(seed) {}

void CatchSummary::on_truth(int64_t utime, bool rolling, const Eigen::Vector2d& ball_b_mm,
                            int last_ball, bool last_caught, bool last_oracle_reachable,
                            const std::string& last_reason,
                            const Eigen::Isometry3d& true_board_to_camera) {
  true_pose_ = true_board_to_camera;
  if (rolling) {
    truth_by_utime_[utime] = ball_b_mm;
    // Outputs arrive within a few frames: keep about two seconds at 60 Hz.
    while (truth_by_utime_.size() > 120) truth_by_utime_.erase(truth_by_utime_.begin());
  }
  if (last_ball >= 0 && last_ball != last_ball_) {
    last_ball_ = last_ball;
    BallOutcome o;
    o.ball = last_ball;
    o.caught = last_caught;
    o.oracle_reachable = last_oracle_reachable;
    o.reason = last_reason;
    if (!last_caught) {
      const auto it = tracks_.find(last_ball);
      classify_miss(it != tracks_.end() ? it->second : BallTrack{}, kToleranceMm, kLateLeadS, o);
    }
    outcomes_.push_back(o);
    tracks_.erase(tracks_.begin(), tracks_.upper_bound(last_ball));
  }
}

void CatchSummary::on_world(int64_t capture_utime, double latency_ms,
                            const std::optional<Eigen::Vector2d>& position_b_mm) {
  ++world_outputs_;
  if (last_world_utime_ > 0 && capture_utime > last_world_utime_)
    update_ms_.add(static_cast<double>(capture_utime - last_world_utime_) / 1e3);
  last_world_utime_ = capture_utime;
  throughput_ms_.add(latency_ms);
  if (!position_b_mm) return;
  const auto it = truth_by_utime_.find(capture_utime);
  if (it != truth_by_utime_.end()) position_error_mm_.add((*position_b_mm - it->second).norm());
}

void CatchSummary::on_ball_truth(int64_t utime, int ball, bool rolling,
                                 const Eigen::Vector2d& ball_b_mm, double true_exit_x_b_mm,
                                 int64_t true_exit_utime) {
  if (!rolling || ball < 0 || ball <= last_ball_) return;
  BallTrack& t = tracks_[ball];
  t.ball = ball;
  t.true_exit_x_b_mm = true_exit_x_b_mm;
  t.true_exit_utime = true_exit_utime;
  rolling_ball_by_utime_[utime] = {ball, ball_b_mm};
  while (rolling_ball_by_utime_.size() > 120)
    rolling_ball_by_utime_.erase(rolling_ball_by_utime_.begin());
}

void CatchSummary::on_prediction(int64_t capture_utime, bool tracking, bool has_prediction,
                                 double exit_x_b_mm,
                                 const std::optional<Eigen::Vector2d>& position_b_mm) {
  const auto it = rolling_ball_by_utime_.find(capture_utime);
  if (it == rolling_ball_by_utime_.end()) return;  // no ball rolled in that frame
  const auto t = tracks_.find(it->second.first);
  if (t == tracks_.end()) return;
  BallTrack& track = t->second;
  const Eigen::Vector2d& truth = it->second.second;
  if (tracking && !std::isfinite(track.first_tracked_y_mm)) track.first_tracked_y_mm = truth.y();
  if (tracking && position_b_mm) {
    const double e = (*position_b_mm - truth).norm();
    if (!(track.max_track_error_mm >= e)) track.max_track_error_mm = e;
    if (e > 50.0 && !std::isfinite(track.strayed_at_y_mm)) track.strayed_at_y_mm = truth.y();
  }
  if (has_prediction && std::isfinite(exit_x_b_mm))
    track.predictions.emplace_back(capture_utime, exit_x_b_mm);
}

void CatchSummary::on_board_pose(const Eigen::Isometry3d& board_to_camera) {
  measured_pose_ = board_to_camera;
}

void CatchSummary::on_sched_status(const std::string& host, bool rt, int64_t deadline_misses) {
  hosts_[host] = {rt, deadline_misses};
}

void CatchSummary::on_task(const std::string& process, const std::string& task, double exec_p50_us,
                           double exec_p99_us, int64_t jobs, int64_t deadline_misses) {
  tasks_[process + "/" + task] = {{"exec_p50_ms", exec_p50_us / 1e3},
                                  {"exec_p99_ms", exec_p99_us / 1e3},
                                  {"jobs", jobs},
                                  {"deadline_misses", deadline_misses}};
}

int CatchSummary::caught() const {
  int n = 0;
  for (const auto& o : outcomes_) n += o.caught ? 1 : 0;
  return n;
}

std::string CatchSummary::status_line() const {
  int reachable = 0;
  for (const auto& o : outcomes_) reachable += o.oracle_reachable ? 1 : 0;
  return fmt::format(
      "balls {} caught {} (oracle-reachable {}), world outputs {}, throughput p99 "
      "{:.2f} ms, position error p99 {:.2f} mm",
      balls(), caught(), reachable, world_outputs_,
      throughput_ms_.empty() ? 0.0 : throughput_ms_.percentile(99),
      position_error_mm_.empty() ? 0.0 : position_error_mm_.percentile(99));
}

nlohmann::json CatchSummary::to_json() const {
  nlohmann::json j;
  j["scenario"] = "catch";
  j["seed"] = seed_;
  j["balls"] = balls();
  j["caught"] = caught();
  int reachable = 0, caught_reachable = 0;
  nlohmann::json missed = nlohmann::json::array();
  std::map<std::string, int> kinds, reachable_kinds;
  auto number = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); };
  for (const auto& o : outcomes_) {
    reachable += o.oracle_reachable ? 1 : 0;
    caught_reachable += (o.oracle_reachable && o.caught) ? 1 : 0;
    if (!o.caught) {
      missed.push_back({{"ball", o.ball},
                        {"reason", o.reason},
                        {"oracle_reachable", o.oracle_reachable},
                        {"kind", o.kind},
                        {"prediction_error_mm", number(o.prediction_error_mm)},
                        {"lead_s", number(o.lead_s)},
                        {"first_tracked_y_mm", number(o.first_tracked_y_mm)},
                        {"strayed_at_y_mm", number(o.strayed_at_y_mm)},
                        {"max_track_error_mm", number(o.max_track_error_mm)}});
      ++kinds[o.kind];
      if (o.oracle_reachable) ++reachable_kinds[o.kind];
    }
  }
  j["missed"] = missed;
  j["missed_kinds"] = kinds;
  j["missed_kinds_oracle_reachable"] = reachable_kinds;
  j["oracle_reachable"] = reachable;
  j["caught_of_oracle_reachable"] = caught_reachable;
  j["update_ms"] = percentiles(update_ms_);
  j["throughput_ms"] = percentiles(throughput_ms_);
  j["position_error_mm"] = percentiles(position_error_mm_);
  j["world_outputs"] = world_outputs_;
  if (true_pose_ && measured_pose_) {
    // Camera pose error: where the camera is (board frame) and how it is turned.
    const Eigen::Vector3d c_true = true_pose_->inverse().translation();
    const Eigen::Vector3d c_meas = measured_pose_->inverse().translation();
    const Eigen::AngleAxisd d(true_pose_->linear().transpose() * measured_pose_->linear());
    j["camera_pose_error_mm"] = (c_true - c_meas).norm();
    j["camera_pose_error_deg"] = std::abs(d.angle()) * 180.0 / M_PI;
  } else {
    j["camera_pose_error_mm"] = nullptr;
    j["camera_pose_error_deg"] = nullptr;
  }
  int64_t misses = 0;
  bool rt = !hosts_.empty();
  for (const auto& [host, h] : hosts_) {
    rt = rt && h.first;
    misses = add_count(misses, h.second);
  }
  j["deadline_misses"] = misses;
  j["tasks"] = tasks_;
  j["rt"] = rt;
  return j;
}

}  // namespace ephor::catching
