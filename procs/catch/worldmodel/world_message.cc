#include "procs/catch/worldmodel/world_message.h"

#include <cmath>
#include <limits>

namespace ephor::catching {

std::optional<Eigen::Vector2d> centroid_of(const catch_ball_t& ball, bool* bad) {
  *bad = false;
  if (!ball.found) return std::nullopt;
  if (!std::isfinite(ball.u) || !std::isfinite(ball.v)) {
    *bad = true;
    return std::nullopt;
  }
  return Eigen::Vector2d(ball.u, ball.v);
}

catch_world_t world_message_of(const BallFrame& f, const catch_ball_t& ball) {
  catch_world_t m{};
  m.utime = ball.utime;
  m.frame_index = ball.frame_index;
  m.ball_id = f.ball_id;
  switch (f.status) {
    case BallStatus::kNoBall:
      m.status = catch_world_t::STATUS_NO_BALL;
      break;
    case BallStatus::kTracking:
      m.status = catch_world_t::STATUS_TRACKING;
      break;
    case BallStatus::kRejected:
      m.status = catch_world_t::STATUS_REJECTED;
      break;
    case BallStatus::kExited:
      m.status = catch_world_t::STATUS_EXITED;
      break;
  }
  if (f.reason != RejectReason::kNone) m.reason = to_string(f.reason);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (int k = 0; k < 2; ++k) {
    m.position_b_mm[k] = f.has_state ? f.position_b_mm[k] : nan;
    m.velocity_b_mm_s[k] = f.has_state ? f.velocity_b_mm_s[k] : nan;
    m.measured_b_mm[k] = f.has_measurement ? f.measured_b_mm[k] : nan;
  }
  for (int k = 0; k < 3; ++k) m.position_w_mm[k] = f.has_state ? f.position_w_mm[k] : nan;
  m.has_prediction = f.has_prediction;
  if (f.has_prediction) {
    m.exit_x_b_mm = f.exit.exit_x_b_mm;
    m.exit_sigma_mm = f.exit.sigma_exit_x_mm;
    m.exit_utime = f.exit_utime;
    m.exit_sigma_s = f.exit.sigma_exit_time_s;
    for (int k = 0; k < 3; ++k) m.catch_point_w_mm[k] = f.exit.catch_point_w_mm[k];
    m.catch_utime = f.catch_utime;
    if (f.has_spread) {
      // With --spread-samples: the exit and catch point Prim aims at are the
      // cover of the prediction's spread (ExitSpread), not the mean's, and
      // the exit's sigma is the standard deviation of the sampled exits.
      m.exit_x_b_mm = f.spread.cover_exit_x_b_mm;
      m.exit_sigma_mm = f.spread.exit_x_sd_mm;
      for (int k = 0; k < 3; ++k) m.catch_point_w_mm[k] = f.spread.cover_point_w_mm[k];
      m.catch_utime = f.cover_catch_utime;
    }
  }
  return m;
}

}  // namespace ephor::catching
