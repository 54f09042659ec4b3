#include "common/catch/worldmodel/ball_kalman_filter.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/Cholesky>

namespace ephor::catching {

namespace {
bool finite_non_negative(double v) { return std::isfinite(v) && v >= 0.0; }
}  // namespace

double first_contact(const Eigen::Vector2d& p0, const Eigen::Vector2d& p1,
                     const Eigen::Vector2d& centre, double reach_mm) {
  // |p0 + u d - c|^2 = R^2: a u^2 + 2 b u + q = 0, the smaller root.
  const Eigen::Vector2d d = p1 - p0, f = p0 - centre;
  const double a = d.squaredNorm(), b = f.dot(d), q = f.squaredNorm() - reach_mm * reach_mm;
  if (q <= 0.0 || a <= 1e-18) return 0.0;  // inside already (or no motion)
  const double disc = b * b - a * q;
  if (disc < 0.0) return 1.0;
  return std::clamp((-b - std::sqrt(disc)) / a, 0.0, 1.0);
}

BallKalmanFilter::BallKalmanFilter(const BallKalmanParams& params) : params_(params) {
  if (!std::isfinite(params.acceleration_mm_s2) ||
      !finite_non_negative(params.accel_sigma_x_mm_s2) ||
      !finite_non_negative(params.accel_sigma_y_mm_s2) ||
      !(params.initial_velocity_sigma_mm_s > 0.0) ||
      !std::isfinite(params.initial_velocity_sigma_mm_s) ||
      !std::isfinite(params.bounce_nis_threshold) ||
      !finite_non_negative(params.bounce_velocity_sigma_mm_s) ||
      !finite_non_negative(params.peg_position_sigma_mm) ||
      !finite_non_negative(params.restitution_sigma) ||
      !(params.bounce_min_cos > 0.0 && params.bounce_min_cos <= 1.0)) {
    throw std::invalid_argument(
        "BallKalmanFilter: parameters must be finite, sigmas >= 0 and the initial velocity "
        "sigma > 0, bounce_min_cos in (0, 1]");
  }
}

void BallKalmanFilter::reset() {
  initialised_ = false;
  x_.setZero();
  p_.setZero();
  since_update_s_ = 0.0;
}

void BallKalmanFilter::initialise(const Eigen::Vector2d& z, const Eigen::Matrix2d& r,
                                  const Eigen::Vector2d& velocity) {
  x_.head<2>() = z;
  x_.tail<2>() = velocity;
  p_.setZero();
  p_.topLeftCorner<2, 2>() = r;
  const double sv = params_.initial_velocity_sigma_mm_s;
  p_.bottomRightCorner<2, 2>() = Eigen::Matrix2d::Identity() * (sv * sv);
  initialised_ = true;
  since_update_s_ = 0.0;
}

void BallKalmanFilter::set_pegs(std::vector<Eigen::Vector2d> centres_b_mm, double reach_mm,
                                double restitution) {
  for (const auto& c : centres_b_mm)
    if (!c.allFinite()) throw std::invalid_argument("BallKalmanFilter: a peg centre is not finite");
  if (!centres_b_mm.empty() && !(reach_mm > 0.0 && std::isfinite(reach_mm)))
    throw std::invalid_argument("BallKalmanFilter: the peg reach must be > 0");
  if (!(restitution >= 0.0 && restitution <= 1.0))
    throw std::invalid_argument("BallKalmanFilter: the restitution must be in [0, 1]");
  pegs_ = std::move(centres_b_mm);
  peg_reach_mm_ = reach_mm;
  restitution_ = restitution;
}

Eigen::Matrix2d BallKalmanFilter::bounce_velocity_covariance(const Eigen::Vector2d& v_in,
                                                             const Eigen::Vector2d& n,
                                                             const Eigen::Matrix2d& position_cov,
                                                             double rest_s) {
  last_bounce_rest_s_ = std::max(0.0, rest_s);
  const double speed = v_in.norm();
  if (!(speed > 1e-9)) return Eigen::Matrix2d::Zero();
  const Eigen::Vector2d t(-n.y(), n.x());
  const double vn = v_in.dot(n), vt = v_in.dot(t);
  // The impact offset's variance: the survey's per axis, and the ball's
  // position across its path.
  const Eigen::Vector2d across(-v_in.y() / speed, v_in.x() / speed);
  const double var_b = params_.peg_position_sigma_mm * params_.peg_position_sigma_mm +
                       across.dot(position_cov * across);
  const double cos_alpha = std::max(params_.bounce_min_cos, std::abs(vn) / speed);
  const double var_theta = var_b / (peg_reach_mm_ * peg_reach_mm_ * cos_alpha * cos_alpha);
  const Eigen::Vector2d g = -(1.0 + restitution_) * (vt * n + vn * t);
  const double se = params_.restitution_sigma;
  return var_theta * g * g.transpose() + se * se * vn * vn * n * n.transpose();
}

void BallKalmanFilter::predict(double dt_s) {
  if (!initialised_ || !(dt_s > 0.0) || !std::isfinite(dt_s)) return;
  const double t = dt_s, a = params_.acceleration_mm_s2;
  // The velocity's reflections on the way (identity without a bounce), and
  // the bounces' own uncertainty, of (position, velocity) at the end of
  // the step.
  Eigen::Matrix2d reflect = Eigen::Matrix2d::Identity();
  Eigen::Matrix4d bounce_q = Eigen::Matrix4d::Zero();
  const Eigen::Matrix2d position_cov = p_.topLeftCorner<2, 2>();
  if (pegs_.empty()) {
    x_(0) += x_(2) * t;
    x_(1) += x_(3) * t + 0.5 * a * t * t;
    x_(3) += a * t;
  } else {
    // 2 ms steps, at most 100 000 (a longer step is coarser, still defined).
    const int steps = static_cast<int>(std::clamp(std::ceil(t / 0.002), 1.0, 1e5));
    const double h = t / steps;
    for (int k = 0; k < steps; ++k) {
      const Eigen::Vector2d p0 = x_.head<2>();
      x_(0) += x_(2) * h;
      x_(1) += x_(3) * h + 0.5 * a * h * h;
      x_(3) += a * h;
      for (const auto& c : pegs_) {
        const Eigen::Vector2d d = x_.head<2>() - c;
        const double dist = d.norm();
        if (dist >= peg_reach_mm_ || dist <= 1e-9) continue;
        // The normal where the ball met the peg (on the step's chord), not
        // where the step left it inside: 2 mm deep at 1 m/s turns a
        // glancing contact's normal by several degrees.
        const double u = first_contact(p0, x_.head<2>(), c, peg_reach_mm_);
        const Eigen::Vector2d contact = p0 + u * (x_.head<2>() - p0);
        const Eigen::Vector2d n = (contact - c).normalized();
        const double vn = x_.tail<2>().dot(n);
        if (vn >= 0.0) continue;
        const Eigen::Matrix2d m =
            Eigen::Matrix2d::Identity() - (1.0 + restitution_) * n * n.transpose();
        const Eigen::Vector2d v_in = x_.tail<2>();
        bounce_q.bottomRightCorner<2, 2>() = m * bounce_q.bottomRightCorner<2, 2>() * m.transpose();
        bounce_q.bottomRightCorner<2, 2>() +=
            bounce_velocity_covariance(v_in, n, position_cov, t - (k + 1) * h);
        x_.tail<2>() = m * x_.tail<2>();
        x_.head<2>() = c + n * peg_reach_mm_ + x_.tail<2>() * ((1.0 - u) * h);
        reflect = m * reflect;
        ++peg_bounces_;
      }
    }
  }
  // P = F P F' written out by blocks (F = [I, T I; 0, I]).
  const Eigen::Matrix2d ppp = p_.topLeftCorner<2, 2>();
  const Eigen::Matrix2d ppv = p_.topRightCorner<2, 2>();
  const Eigen::Matrix2d pvv = p_.bottomRightCorner<2, 2>();
  const Eigen::Matrix2d new_ppv = ppv + t * pvv;
  p_.topLeftCorner<2, 2>() = ppp + t * (ppv + ppv.transpose()) + t * t * pvv;
  p_.topRightCorner<2, 2>() = new_ppv;
  p_.bottomLeftCorner<2, 2>() = new_ppv.transpose();
  const double t2 = t * t;
  for (int i = 0; i < 2; ++i) {
    const double sigma = i == 0 ? params_.accel_sigma_x_mm_s2 : params_.accel_sigma_y_mm_s2;
    const double q = sigma * sigma;
    p_(i, i) += q * t2 * t2 / 4.0;
    p_(i, i + 2) += q * t2 * t / 2.0;
    p_(i + 2, i) += q * t2 * t / 2.0;
    p_(i + 2, i + 2) += q * t2;
  }
  if (!reflect.isIdentity()) {
    Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
    m.bottomRightCorner<2, 2>() = reflect;
    p_ = m * p_ * m.transpose();
    // The bounce's velocity error, and what it moved the ball in the rest
    // of the step (last_bounce_rest_s_, the last bounce's; a second bounce
    // within one step is rare and shares it).
    const Eigen::Matrix2d qv = bounce_q.bottomRightCorner<2, 2>();
    const double rest = last_bounce_rest_s_;
    p_.topLeftCorner<2, 2>() += rest * rest * qv;
    p_.topRightCorner<2, 2>() += rest * qv;
    p_.bottomLeftCorner<2, 2>() += rest * qv;
    p_.bottomRightCorner<2, 2>() += qv;
    p_ = 0.5 * (p_ + p_.transpose());
  }
  since_update_s_ += t;
}

KalmanUpdateResult BallKalmanFilter::update(const Eigen::Vector2d& z, const Eigen::Matrix2d& r) {
  KalmanUpdateResult result;
  if (!initialised_ || !z.allFinite() || !r.allFinite()) return result;
  result.innovation = z - x_.head<2>();
  Eigen::Matrix2d s = p_.topLeftCorner<2, 2>() + r;
  result.nis = result.innovation.dot(s.ldlt().solve(result.innovation));
  if (params_.bounce_nis_threshold > 0.0 && result.nis > params_.bounce_nis_threshold) {
    // A velocity impulse dv at an unknown time s, uniform in the interval T
    // since the last update: it moved the ball by dv (T - s), so
    // P += Qb [T^2/3, T/2; T/2, 1] per axis. The position-velocity
    // correlation of sqrt(3)/2 (not 1) keeps a quarter of Qb in the velocity
    // after this update: one position cannot tell a large late bounce from
    // a small early one, the next frames do.
    const double t = since_update_s_;
    const double qb = params_.bounce_velocity_sigma_mm_s * params_.bounce_velocity_sigma_mm_s;
    for (int i = 0; i < 2; ++i) {
      p_(i, i) += qb * t * t / 3.0;
      p_(i, i + 2) += qb * t / 2.0;
      p_(i + 2, i) += qb * t / 2.0;
      p_(i + 2, i + 2) += qb;
    }
    s = p_.topLeftCorner<2, 2>() + r;
    result.bounce = true;
    ++bounces_;
  }
  // K = P H' S^-1 with H = [I 0].
  const Eigen::Matrix<double, 4, 2> pht = p_.leftCols<2>();
  const Eigen::Matrix<double, 4, 2> k = s.ldlt().solve(pht.transpose()).transpose();
  x_ += k * result.innovation;
  // Joseph form keeps P symmetric and positive through the bounce's large
  // gains: P = (I - K H) P (I - K H)' + K R K'.
  Covariance ikh = Covariance::Identity();
  ikh.leftCols<2>() -= k;
  p_ = ikh * p_ * ikh.transpose() + k * r * k.transpose();
  p_ = 0.5 * (p_ + p_.transpose());
  since_update_s_ = 0.0;
  ++updates_;
  result.applied = true;
  return result;
}

}  // namespace ephor::catching
