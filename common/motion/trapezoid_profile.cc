#include "common/motion/trapezoid_profile.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ephor::arm {

TrapezoidProfile::TrapezoidProfile(double length, double max_speed, double max_accel)
    : length_(length), accel_(max_accel) {
  if (!(length >= 0.0) || !std::isfinite(length) || !(max_speed > 0.0) ||
      !std::isfinite(max_speed) || !(max_accel > 0.0) || !std::isfinite(max_accel))
    throw std::invalid_argument("TrapezoidProfile: need length >= 0, speed > 0 and accel > 0");
  // Triangle when the ramps alone would overshoot half the path.
  peak_ = std::min(max_speed, std::sqrt(length * max_accel));
  t_ramp_ = peak_ / max_accel;
  const double ramp_length = peak_ * t_ramp_;  // both ramps together
  duration_ = length == 0.0 ? 0.0 : 2.0 * t_ramp_ + (length - ramp_length) / peak_;
}

double TrapezoidProfile::position(double t) const {
  if (duration_ <= 0.0) return length_;
  t = std::clamp(t, 0.0, duration_);
  if (t < t_ramp_) return 0.5 * accel_ * t * t;
  if (t <= duration_ - t_ramp_) return 0.5 * peak_ * t_ramp_ + peak_ * (t - t_ramp_);
  const double r = duration_ - t;
  return length_ - 0.5 * accel_ * r * r;
}

double TrapezoidProfile::speed(double t) const {
  if (duration_ <= 0.0 || t <= 0.0 || t >= duration_) return 0.0;
  if (t < t_ramp_) return accel_ * t;
  if (t <= duration_ - t_ramp_) return peak_;
  return accel_ * (duration_ - t);
}

}  // namespace ephor::arm
