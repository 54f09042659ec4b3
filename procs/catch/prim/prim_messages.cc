#include "procs/catch/prim/prim_messages.h"

#include <cmath>

namespace ephor::catching {

std::optional<CatchPrediction> prediction_of(const catch_world_t& world, bool* bad) {
  *bad = false;
  if (!world.has_prediction || world.status == catch_world_t::STATUS_NO_BALL) return std::nullopt;
  CatchPrediction p;
  p.ball_id = world.ball_id;
  p.catch_utime = world.catch_utime;
  p.catch_point_w_mm = Eigen::Vector3d(world.catch_point_w_mm[0], world.catch_point_w_mm[1],
                                       world.catch_point_w_mm[2]);
  p.sigma_mm = world.exit_sigma_mm;
  if (!p.catch_point_w_mm.allFinite() || !std::isfinite(p.sigma_mm)) {
    *bad = true;
    return std::nullopt;
  }
  return p;
}

std::optional<Eigen::Vector3d> cup_of(const arm_state_t& state) {
  const Eigen::Vector3d p(state.x_mm, state.y_mm, state.z_mm);
  if (!p.allFinite()) return std::nullopt;
  return p;
}

arm_goal_t goal_message_of(const CatchGoal& goal, const catch_world_t& world, int64_t run_id) {
  arm_goal_t msg{};
  msg.goal_id = run_id + goal.goal_id;
  msg.kind = arm_goal_t::KIND_POSE;
  for (int k = 0; k < 3; ++k) msg.position_mm[k] = goal.point_w_mm[k];
  msg.theta_rad = 0.0f;
  msg.max_speed_mm_s = 0.0f;  // the arm's own cap
  msg.source_frame_utime = world.utime;
  msg.target_object = world.ball_id;
  return msg;
}

}  // namespace ephor::catching
