#include "common/sphere/world/relative_motion.h"

#include <stdexcept>
#include <string>

namespace ephor::sphere {

Eigen::Vector3d RelativeMotionConfig::table1_drift(double distance_m) {
  const double v = table1_xy_speed_m_s(distance_m);
  return {v, v, -kTable1ZSpeedMS};
}

RelativeMotion::RelativeMotion(const RelativeMotionConfig& config)
    : config_(config),
      p0_(config.start_position_m),
      target_velocity_(config.target_velocity_m_s),
      chaser_velocity_(config.chaser_velocity_m_s) {
  if (!config.start_position_m.allFinite() || !config.target_velocity_m_s.allFinite() ||
      !config.chaser_velocity_m_s.allFinite()) {
    throw std::invalid_argument("RelativeMotion: start position and velocities must be finite");
  }
  if (!(config.max_accel_m_s2 >= 0.0 && config.max_accel_m_s2 < 100.0)) {
    throw std::invalid_argument("RelativeMotion: max acceleration must be in [0, 100) m/s^2");
  }
  if (!(config.window_s > 0.0 && config.window_s <= 10.0)) {
    throw std::invalid_argument("RelativeMotion: window must be in (0, 10] s");
  }
}

SphereTrajectory RelativeMotion::begin_window(double t_begin_s,
                                              const Eigen::Vector3d& commanded_chaser_m_s) {
  if (!(t_begin_s >= t0_)) {
    throw std::invalid_argument("RelativeMotion: window at " + std::to_string(t_begin_s) +
                                " s starts before the current one (" + std::to_string(t0_) + " s)");
  }
  p0_ = position_at(t_begin_s);
  t0_ = t_begin_s;
  if (commanded_chaser_m_s.allFinite()) {
    const Eigen::Vector3d change = commanded_chaser_m_s - chaser_velocity_;
    const double max_change = config_.max_accel_m_s2 * config_.window_s;
    const double norm = change.norm();
    chaser_velocity_ += norm > max_change ? change * (max_change / norm) : change;
  }
  return trajectory();
}

void RelativeMotion::reset_target(double t_s, const Eigen::Vector3d& position_m,
                                  const Eigen::Vector3d& target_velocity_m_s) {
  t0_ = t_s;
  p0_ = position_m;
  target_velocity_ = target_velocity_m_s;
}

SphereTrajectory RelativeMotion::trajectory() const {
  SphereTrajectory s;
  s.t0_s = t0_;
  s.position_at_t0_m = p0_;
  s.velocity_m_s = relative_velocity();
  return s;
}

}  // namespace ephor::sphere
