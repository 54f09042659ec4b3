#include "procs/catch/monitor/catch_monitor_feed.h"

#include <cstdint>

#include <Eigen/Geometry>

#include "common/geometry/message_pose.h"
#include "common/runtime/counts.h"

namespace ephor::catching {
namespace {}  // namespace

std::optional<std::string> CatchMonitorFeed::on_truth(const catch_truth_t& m) {
  const bool rolling = m.phase == catch_truth_t::PHASE_ROLLING;
  const Eigen::Vector2d ball_b_mm(m.ball_b_mm[0], m.ball_b_mm[1]);
  summary_.on_truth(m.utime, rolling, ball_b_mm, m.last_ball, m.last_caught,
                    m.last_oracle_reachable, m.last_reason,
                    geometry::pose_of(m.board_to_camera_r, m.board_to_camera_t_mm));
  summary_.on_ball_truth(m.utime, m.ball, rolling, ball_b_mm, m.exit_x_b_mm, m.exit_utime);
  if (m.last_ball < 0 || m.last_ball == last_logged_) return std::nullopt;
  last_logged_ = m.last_ball;
  return "ball " + std::to_string(m.last_ball) + ": " + (m.last_caught ? "" : "missed: ") +
         m.last_reason;
}

void CatchMonitorFeed::on_world(const catch_world_t& m) {
  const bool tracking = m.status == catch_world_t::STATUS_TRACKING;
  std::optional<Eigen::Vector2d> p;
  if (tracking) p = Eigen::Vector2d(m.position_b_mm[0], m.position_b_mm[1]);
  summary_.on_world(m.utime, m.latency_ms, p);
  summary_.on_prediction(m.utime, tracking, m.has_prediction != 0, m.exit_x_b_mm, p);
}

void CatchMonitorFeed::on_board_pose(const catch_board_pose_t& m) {
  if (m.valid) summary_.on_board_pose(geometry::pose_of(m.r, m.t_mm));
}

void CatchMonitorFeed::on_sched_status(const sched_status_t& m) {
  int64_t misses = 0;
  for (const auto& t : m.tasks) misses = add_count(misses, t.deadline_misses);
  summary_.on_sched_status(m.host, m.rt != 0, misses);
  for (const auto& t : m.tasks)
    summary_.on_task(t.process, t.task, t.exec_p50_us, t.exec_p99_us, t.jobs, t.deadline_misses);
}

}  // namespace ephor::catching
