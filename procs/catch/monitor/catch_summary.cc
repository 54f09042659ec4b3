#include "procs/catch/monitor/catch_summary.h"

#include <cmath>

#include <fmt/format.h>

namespace ephor::catching {

namespace {

nlohmann::json percentiles(const RollingStats& s) {
  if (s.empty()) return {{"p50", nullptr}, {"p99", nullptr}, {"n", 0}};
  return {{"p50", s.percentile(50)}, {"p99", s.percentile(99)}, {"max", s.max()}, {"n", s.size()}};
}

}  // namespace

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
    outcomes_.push_back({last_ball, last_caught, last_oracle_reachable, last_reason});
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
  for (const auto& o : outcomes_) {
    reachable += o.oracle_reachable ? 1 : 0;
    caught_reachable += (o.oracle_reachable && o.caught) ? 1 : 0;
    if (!o.caught)
      missed.push_back(
          {{"ball", o.ball}, {"reason", o.reason}, {"oracle_reachable", o.oracle_reachable}});
  }
  j["missed"] = missed;
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
    misses += h.second;
  }
  j["deadline_misses"] = misses;
  j["tasks"] = tasks_;
  j["rt"] = rt;
  return j;
}

}  // namespace ephor::catching
