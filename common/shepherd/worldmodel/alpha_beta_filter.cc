#include "common/shepherd/worldmodel/alpha_beta_filter.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace ephor::worldmodel {

double tracking_index(const NoiseModel& noise) {
  const bool ok = std::isfinite(noise.plant_noise) && noise.plant_noise > 0.0 &&
                  std::isfinite(noise.measurement_noise) && noise.measurement_noise > 0.0 &&
                  std::isfinite(noise.step) && noise.step > 0.0;
  if (!ok)
    throw std::invalid_argument("alpha-beta noise model: plant noise " +
                                std::to_string(noise.plant_noise) + ", measurement noise " +
                                std::to_string(noise.measurement_noise) + " and step " +
                                std::to_string(noise.step) + " must all be finite and > 0");
  return noise.plant_noise * noise.step * noise.step / noise.measurement_noise;
}

AlphaBetaGains gains_for_tracking_index(double lambda) {
  if (!(std::isfinite(lambda) && lambda > 0.0))
    throw std::invalid_argument("tracking index must be finite and > 0, got " +
                                std::to_string(lambda));
  const double l2 = lambda * lambda;
  const double root = std::sqrt(l2 + 8.0 * lambda);
  return {-(l2 + 8.0 * lambda - (lambda + 4.0) * root) / 8.0,
          (l2 + 4.0 * lambda - lambda * root) / 4.0};
}

AlphaBetaFilter::AlphaBetaFilter(AlphaBetaGains gains, double maneuver_gate, int maneuver_confirm)
    : gains_(gains), maneuver_gate_(maneuver_gate), maneuver_confirm_(maneuver_confirm) {
  if (!(std::isfinite(maneuver_gate) && maneuver_gate >= 0.0))
    throw std::invalid_argument("manoeuvre gate must be finite and >= 0, got " +
                                std::to_string(maneuver_gate));
  if (maneuver_confirm < 1)
    throw std::invalid_argument("manoeuvre confirmation must be >= 1 measurement, got " +
                                std::to_string(maneuver_confirm));
  if (!(gains.alpha > 0.0 && gains.alpha <= 1.0 && gains.beta > 0.0 &&
        gains.beta < 4.0 - 2.0 * gains.alpha))
    throw std::invalid_argument("alpha-beta gains outside the stable region: alpha " +
                                std::to_string(gains.alpha) + ", beta " +
                                std::to_string(gains.beta));
}

AlphaBetaFilter::AlphaBetaFilter(const NoiseModel& noise, double maneuver_gate,
                                 int maneuver_confirm)
    : AlphaBetaFilter(gains_for_tracking_index(tracking_index(noise)), maneuver_gate,
                      maneuver_confirm) {}

void AlphaBetaFilter::predict(double dt_s) {
  if (!(std::isfinite(dt_s) && dt_s >= 0.0)) return;
  position_ += velocity_ * dt_s;
  since_update_s_ += dt_s;
  clock_s_ += dt_s;
}

bool AlphaBetaFilter::update(const Eigen::Vector2d& z) {
  if (!z.allFinite()) return false;
  if (updates_ == 0) {
    position_ = z;
    remember(z);
    since_update_s_ = 0.0;
    updates_ = 1;
    return true;
  }
  // Two updates at the same instant carry no velocity information.
  if (!(since_update_s_ > 0.0)) {
    position_ += gains_.alpha * (z - position_);
    remember(z);
    return true;
  }
  if (maneuver_gate_ > 0.0 && updates_ >= 3 && (z - position_).norm() > maneuver_gate_) {
    ++outside_run_;
    if (outside_run_ >= maneuver_confirm_) {
      // The measurements keep contradicting constant velocity: start again
      // from a least-squares line through the last three measurements.
      remember(z);
      const int n = recent_n_;
      double t_mean = 0.0;
      Eigen::Vector2d z_mean = Eigen::Vector2d::Zero();
      for (int i = 0; i < n; ++i) {
        t_mean += recent_t_[i] / n;
        z_mean += recent_z_[i] / n;
      }
      double stt = 0.0;
      Eigen::Vector2d stz = Eigen::Vector2d::Zero();
      for (int i = 0; i < n; ++i) {
        stt += (recent_t_[i] - t_mean) * (recent_t_[i] - t_mean);
        stz += (recent_t_[i] - t_mean) * (recent_z_[i] - z_mean);
      }
      if (n >= 2 && stt > 0.0) {
        const Eigen::Vector2d v = stz / stt;
        restart(z_mean + v * (clock_s_ - t_mean), v);
        ++maneuvers_;
        return true;
      }
    }
    // Not confirmed yet: hold it back (an outlier must not move the filter).
    ++held_back_;
    remember(z);
    return true;
  }
  outside_run_ = 0;
  const double n = updates_ + 1;
  const double alpha = std::max(gains_.alpha, 2.0 * (2.0 * n - 1.0) / (n * (n + 1.0)));
  const double beta = std::max(gains_.beta, 6.0 / (n * (n + 1.0)));
  const Eigen::Vector2d residual = z - position_;
  position_ += alpha * residual;
  velocity_ += (beta / since_update_s_) * residual;
  since_update_s_ = 0.0;
  remember(z);
  ++updates_;
  return true;
}

void AlphaBetaFilter::remember(const Eigen::Vector2d& z) {
  // Same instant as the newest: replace it (no time base for a slope).
  if (recent_n_ > 0 && recent_t_[recent_n_ - 1] == clock_s_) {
    recent_z_[recent_n_ - 1] = z;
    return;
  }
  if (recent_n_ == 3) {
    recent_z_[0] = recent_z_[1];
    recent_t_[0] = recent_t_[1];
    recent_z_[1] = recent_z_[2];
    recent_t_[1] = recent_t_[2];
    recent_n_ = 2;
  }
  recent_z_[recent_n_] = z;
  recent_t_[recent_n_] = clock_s_;
  ++recent_n_;
}

void AlphaBetaFilter::restart(const Eigen::Vector2d& position, const Eigen::Vector2d& velocity) {
  if (!position.allFinite() || !velocity.allFinite()) return;
  position_ = position;
  velocity_ = velocity;
  since_update_s_ = 0.0;
  outside_run_ = 0;
  updates_ = 2;
}

void AlphaBetaFilter::reset() {
  position_.setZero();
  velocity_.setZero();
  recent_n_ = 0;
  clock_s_ = 0.0;
  outside_run_ = 0;
  since_update_s_ = 0.0;
  updates_ = 0;
}

void AlphaBetaFilter::relocate(const Eigen::Vector2d& z) {
  if (!z.allFinite()) return;
  position_ = z;
  // A new track segment: older measurements say nothing about it.
  recent_n_ = 0;
  remember(z);
  since_update_s_ = 0.0;
  outside_run_ = 0;
  if (updates_ == 0) updates_ = 1;
}

DoubleAlphaBetaFilter::Params DoubleAlphaBetaFilter::Params::from_frame_period(
    double frame_period_s, double gate) {
  Params p;
  p.first.step = frame_period_s;
  p.second.step = frame_period_s * p.subsample;
  p.maneuver_gate = gate;
  return p;
}

DoubleAlphaBetaFilter::Params DoubleAlphaBetaFilter::Params::per_step() {
  Params p;
  p.first = kTable1First;
  p.second = kTable1Second;
  p.maneuver_gate = 0.0;
  return p;
}

DoubleAlphaBetaFilter::DoubleAlphaBetaFilter(const Params& params)
    : subsample_(params.subsample),
      first_(params.first, params.maneuver_gate, params.maneuver_confirm),
      second_(params.second) {
  if (subsample_ < 1)
    throw std::invalid_argument("double alpha-beta filter: subsample must be >= 1, got " +
                                std::to_string(subsample_));
}

void DoubleAlphaBetaFilter::predict(double dt_s) {
  if (!(std::isfinite(dt_s) && dt_s >= 0.0)) return;
  first_.predict(dt_s);
  second_pending_s_ += dt_s;
}

bool DoubleAlphaBetaFilter::update(const Eigen::Vector2d& z) {
  const bool fresh = !first_.initialised();
  const int maneuvers = first_.maneuvers();
  if (!first_.update(z)) return false;
  if (first_.maneuvers() != maneuvers) {
    // The first filter saw a manoeuvre: the second follows at once rather
    // than through its smoothing.
    second_.restart(first_.position(), first_.velocity());
    second_pending_s_ = 0.0;
    first_updates_since_feed_ = 0;
    return true;
  }
  ++first_updates_since_feed_;
  if (fresh || first_updates_since_feed_ >= subsample_) {
    second_.predict(second_pending_s_);
    second_.update(first_.position());
    second_pending_s_ = 0.0;
    first_updates_since_feed_ = 0;
  }
  return true;
}

void DoubleAlphaBetaFilter::reset() {
  first_.reset();
  second_.reset();
  second_pending_s_ = 0.0;
  first_updates_since_feed_ = 0;
}

void DoubleAlphaBetaFilter::relocate(const Eigen::Vector2d& z) {
  first_.relocate(z);
  second_.relocate(z);
  second_pending_s_ = 0.0;
  first_updates_since_feed_ = 0;
}

}  // namespace ephor::worldmodel
