#include "procs/catch/display/catch_display_feed.h"

#include <array>
#include <cstddef>

namespace ephor::catch_display {
namespace {

template <size_t N, class T>
std::array<double, N> arr(const T (&v)[N]) {
  std::array<double, N> a{};
  for (size_t i = 0; i < N; ++i) a[i] = static_cast<double>(v[i]);
  return a;
}

}  // namespace

void CatchDisplayFeed::on_frame(const camera_frame_t& m, int64_t now_us) {
  state_.on_frame(m.frame_index, m.width, m.height, now_us);
}

void CatchDisplayFeed::on_board_pose(const catch_board_pose_t& m, int64_t now_us) {
  BoardPoseView p;
  p.valid = m.valid;
  p.reason = m.reason;
  p.r = arr(m.r);
  p.t_mm = arr(m.t_mm);
  p.circles_px = arr(m.circles_px);
  p.reprojection_rms_px = m.reprojection_rms_px;
  state_.on_board_pose(p, now_us);
}

void CatchDisplayFeed::on_survey(const catch_survey_t& m, int64_t now_us) {
  SurveyView s;
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 2; ++k) s.board_mm[i][k] = m.board_mm[i][k];
    for (int k = 0; k < 3; ++k) s.world_mm[i][k] = m.world_mm[i][k];
  }
  state_.on_survey(s, now_us);
}

void CatchDisplayFeed::on_ball(const catch_ball_t& m, int64_t now_us) {
  BallView b;
  b.frame_index = m.frame_index;
  b.found = m.found;
  b.u = m.u;
  b.v = m.v;
  b.u_blob = m.u_blob;
  b.v_blob = m.v_blob;
  b.area_px = m.area_px;
  for (int i = 0; i < 4; ++i) b.window[static_cast<size_t>(i)] = m.window[i];
  b.exec_ms = m.exec_ms;
  state_.on_ball(b, now_us);
}

void CatchDisplayFeed::on_world(const catch_world_t& m, int64_t now_us) {
  WorldView w;
  w.utime = m.utime;
  w.frame_index = m.frame_index;
  w.status = m.status;
  w.ball_id = m.ball_id;
  w.reason = m.reason;
  w.position_b_mm = arr(m.position_b_mm);
  w.velocity_b_mm_s = arr(m.velocity_b_mm_s);
  w.has_prediction = m.has_prediction;
  w.exit_x_b_mm = m.exit_x_b_mm;
  w.exit_sigma_mm = m.exit_sigma_mm;
  w.exit_utime = m.exit_utime;
  w.exit_sigma_s = m.exit_sigma_s;
  w.catch_point_w_mm = arr(m.catch_point_w_mm);
  w.catch_utime = m.catch_utime;
  w.latency_ms = m.latency_ms;
  state_.on_world(w, now_us);
}

void CatchDisplayFeed::on_truth(const catch_truth_t& m, int64_t now_us) {
  TruthView t;
  t.ball = m.ball;
  t.phase = m.phase;
  t.ball_px = arr(m.ball_px);
  t.incline_deg = m.incline_deg;
  t.balls_done = m.balls_done;
  t.caught = m.caught;
  t.oracle_reachable = m.oracle_reachable;
  t.last_ball = m.last_ball;
  t.last_caught = m.last_caught;
  t.last_oracle_reachable = m.last_oracle_reachable;
  t.last_reason = m.last_reason;
  state_.on_truth(t, now_us);
}

void CatchDisplayFeed::on_arm_state(const arm_state_t& m, int64_t now_us) {
  state_.on_arm({m.x_mm, m.y_mm, m.z_mm, m.moving != 0, m.speed_mm_s}, now_us);
}

}  // namespace ephor::catch_display
