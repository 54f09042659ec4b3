#include "common/sphere/guidance/sphere_tracker.h"

#include <cmath>

#include <Eigen/Cholesky>

namespace ephor::sphere {

Eigen::Vector3d paper_measurement_sigma_m(double distance_m) {
  const double s = 0.008 * std::max(1.0, distance_m / 20.0);
  return Eigen::Vector3d::Constant(s);
}

SphereTracker::SphereTracker(const SphereTrackerConfig& config) : config_(config) {}

void SphereTracker::reset() {
  initialised_ = false;
  rejects_in_a_row_ = 0;
  changes_.clear();
}

void SphereTracker::schedule_velocity_change(double t_s, const Eigen::Vector3d& dv_m_s) {
  if (!std::isfinite(t_s) || !dv_m_s.allFinite()) return;
  if (initialised_ && t_s <= t_) {
    // Already past: the velocity changed then, and the position since.
    x_.segment<3>(3) += dv_m_s;
    x_.head<3>() += dv_m_s * (t_ - t_s);
    return;
  }
  changes_.emplace(t_s, dv_m_s);
}

void SphereTracker::propagate(double t_s, Vector6d& x, Matrix6d& P, double& t,
                              std::multimap<double, Eigen::Vector3d>* consume) const {
  auto step = [&](double to) {
    const double dt = to - t;
    if (dt <= 0.0) return;
    Matrix6d F = Matrix6d::Identity();
    F.block<3, 3>(0, 3) = Eigen::Matrix3d::Identity() * dt;
    const double q = config_.accel_noise_psd;
    Matrix6d Q = Matrix6d::Zero();
    Q.block<3, 3>(0, 0) = Eigen::Matrix3d::Identity() * (q * dt * dt * dt / 3.0);
    Q.block<3, 3>(0, 3) = Eigen::Matrix3d::Identity() * (q * dt * dt / 2.0);
    Q.block<3, 3>(3, 0) = Q.block<3, 3>(0, 3);
    Q.block<3, 3>(3, 3) = Eigen::Matrix3d::Identity() * (q * dt);
    x = F * x;
    P = F * P * F.transpose() + Q;
    t = to;
  };
  for (auto it = changes_.begin(); it != changes_.end() && it->first <= t_s;) {
    step(it->first);
    x.segment<3>(3) += it->second;
    it = consume ? consume->erase(it) : std::next(it);
  }
  step(t_s);
}

void SphereTracker::initialise(double t_s, const Eigen::Vector3d& position_m,
                               const Eigen::Vector3d& sigma_m,
                               const std::optional<Eigen::Vector3d>& velocity_hint_m_s) {
  t_ = t_s;
  x_.head<3>() = position_m;
  const bool hint = velocity_hint_m_s && velocity_hint_m_s->allFinite();
  x_.tail<3>() = hint ? *velocity_hint_m_s : Eigen::Vector3d::Zero();
  const double sv = hint ? config_.hint_velocity_sigma_m_s : config_.initial_velocity_sigma_m_s;
  P_ = Matrix6d::Zero();
  P_.block<3, 3>(0, 0) = sigma_m.cwiseAbs2().asDiagonal();
  P_.block<3, 3>(3, 3) = Eigen::Matrix3d::Identity() * (sv * sv);
  // Burns scheduled before the new track's start are in its velocity already.
  changes_.erase(changes_.begin(), changes_.upper_bound(t_s));
  initialised_ = true;
  rejects_in_a_row_ = 0;
}

SphereTracker::Update SphereTracker::update(
    double t_s, const Eigen::Vector3d& position_m, const Eigen::Vector3d& sigma_m,
    const std::optional<Eigen::Vector3d>& velocity_hint_m_s) {
  if (!initialised_) {
    initialise(t_s, position_m, sigma_m, velocity_hint_m_s);
    return Update::kInitialised;
  }
  if (t_s < t_) return Update::kOutOfOrder;
  Vector6d x = x_;
  Matrix6d P = P_;
  double t = t_;
  propagate(t_s, x, P, t, nullptr);
  const Eigen::Vector3d innovation = position_m - x.head<3>();
  Eigen::Matrix3d R = sigma_m.cwiseAbs2().asDiagonal();
  const Eigen::LDLT<Eigen::Matrix3d> ldlt0(P.block<3, 3>(0, 0) + R);
  const double d2 = innovation.dot(ldlt0.solve(innovation));
  if (!(d2 <= config_.jump_chi2)) {
    if (++rejects_in_a_row_ >= config_.reinit_after_rejects) {
      initialise(t_s, position_m, sigma_m, velocity_hint_m_s);
      return Update::kReinitialised;
    }
    return Update::kRejected;
  }
  rejects_in_a_row_ = 0;
  const bool downweight = d2 > config_.gate_chi2;
  if (downweight) R *= d2 / config_.gate_chi2;
  propagate(t_s, x_, P_, t_, &changes_);
  const Eigen::LDLT<Eigen::Matrix3d> ldlt(P_.block<3, 3>(0, 0) + R);
  // K = P H^T S^-1 with H = [I 0].
  const Eigen::Matrix<double, 6, 3> K = ldlt.solve(P_.block<6, 3>(0, 0).transpose()).transpose();
  x_ += K * innovation;
  Matrix6d IKH = Matrix6d::Identity();
  IKH.block<6, 3>(0, 0) -= K;
  // Joseph form: stays symmetric positive definite.
  P_ = IKH * P_ * IKH.transpose() + K * R * K.transpose();
  return downweight ? Update::kDownweighted : Update::kAccepted;
}

TrackPrediction SphereTracker::predict(double t_s) const {
  Vector6d x = x_;
  Matrix6d P = P_;
  double t = t_;
  if (t_s > t) propagate(t_s, x, P, t, nullptr);
  TrackPrediction p;
  p.t_s = t;
  p.position_m = x.head<3>();
  p.velocity_m_s = x.tail<3>();
  p.position_sigma_m = P.diagonal().head<3>().cwiseSqrt();
  p.velocity_sigma_m_s = P.diagonal().tail<3>().cwiseSqrt();
  return p;
}

}  // namespace ephor::sphere
