#include "common/sphere/guidance/approach_controller.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ephor::sphere {

const char* to_string(ApproachPhase p) {
  switch (p) {
    case ApproachPhase::kAcquire:
      return "acquire";
    case ApproachPhase::kClosing:
      return "closing";
    case ApproachPhase::kFinal:
      return "final";
  }
  return "?";
}

ApproachController::ApproachController(const ApproachConfig& c) : config_(c) {
  const bool ok = c.capture_distance_m > 0 && c.final_distance_m >= 0 && c.final_speed_m_s > 0 &&
                  c.braking_accel_m_s2 > 0 && c.max_closing_m_s >= c.final_speed_m_s &&
                  c.lateral_gain_1_s > 0 && c.max_lateral_m_s > 0 && c.cone_offset_m > 0 &&
                  c.cone_slope >= 0 && c.max_accel_m_s2 > 0 && c.window_s > 0;
  if (!ok) {
    throw std::invalid_argument(
        "ApproachController: distances, speeds, gain, acceleration and window must be positive "
        "(and max closing >= final speed)");
  }
}

Eigen::Vector3d ApproachController::wanted_relative_velocity(const Eigen::Vector3d& p) const {
  const ApproachConfig& c = config_;
  Eigen::Vector3d w;
  // Across the boresight: drive the offset to zero.
  Eigen::Vector2d lateral = -c.lateral_gain_1_s * p.head<2>();
  if (lateral.norm() > c.max_lateral_m_s) lateral *= c.max_lateral_m_s / lateral.norm();
  w.head<2>() = lateral;
  // Along it: the braking profile (a closing speed is a negative dz/dt).
  const double to_go = p.z() - c.capture_distance_m;
  const double beyond_final = std::max(0.0, to_go - c.final_distance_m);
  double closing = std::min(
      c.max_closing_m_s, c.final_speed_m_s + std::sqrt(2.0 * c.braking_accel_m_s2 * beyond_final));
  // Hold back while off the axis: full speed inside the cone, none at twice its radius.
  const double cone = c.cone_offset_m + c.cone_slope * std::max(0.0, to_go);
  const double offset = p.head<2>().norm();
  const double factor = std::clamp(2.0 - offset / cone, 0.0, 1.0);
  closing *= factor;
  w.z() = -closing;
  return w;
}

ApproachCommand ApproachController::command(const Eigen::Vector3d& p, const Eigen::Vector3d& v_pred,
                                            const Eigen::Vector3d& chaser) const {
  ApproachCommand out;
  out.wanted_relative_m_s = wanted_relative_velocity(p);
  out.phase = p.z() - config_.capture_distance_m > config_.final_distance_m
                  ? ApproachPhase::kClosing
                  : ApproachPhase::kFinal;
  // v_rel after = v_pred - (chaser_new - chaser).
  // The budget goes across the boresight first: an offset left to grow
  // while the chaser speeds up along it is what capture cannot afford (at
  // 20 m the sphere drifts 14 cm/s across, 3.6 cm/s along).
  const Eigen::Vector3d need = v_pred - out.wanted_relative_m_s;
  const double budget = config_.max_accel_m_s2 * config_.window_s;
  Eigen::Vector2d lateral = need.head<2>();
  if (lateral.norm() > budget) lateral *= budget / lateral.norm();
  const double z_budget = std::sqrt(std::max(0.0, budget * budget - lateral.squaredNorm()));
  const Eigen::Vector3d change(lateral.x(), lateral.y(), std::clamp(need.z(), -z_budget, z_budget));
  out.chaser_velocity_m_s = chaser + change;
  return out;
}

ApproachCommand ApproachController::hold(const Eigen::Vector3d& chaser) const {
  ApproachCommand out;
  out.phase = ApproachPhase::kAcquire;
  out.chaser_velocity_m_s = chaser;
  return out;
}

}  // namespace ephor::sphere
