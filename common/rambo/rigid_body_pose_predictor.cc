#include "common/rambo/rigid_body_pose_predictor.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/Cholesky>

namespace ephor::rambo {

namespace {

Eigen::Vector3d log_map(const Eigen::Matrix3d& r) {
  const Eigen::AngleAxisd aa(r);
  return aa.angle() * aa.axis();
}

Eigen::Quaterniond exp_map(const Eigen::Vector3d& v) {
  const double a = v.norm();
  if (a < 1e-12) return Eigen::Quaterniond::Identity();
  return Eigen::Quaterniond(Eigen::AngleAxisd(a, v / a));
}

struct State {
  Eigen::Vector4d q;  // w, x, y, z
  Eigen::Vector3d w;
};

State derivative(const State& s, const Eigen::Vector3d& m) {
  State d;
  const double qw = s.q[0], qx = s.q[1], qy = s.q[2], qz = s.q[3];
  const Eigen::Vector3d& w = s.w;
  // q' = 0.5 q (x) (0, w): body-frame rates.
  d.q << -0.5 * (qx * w.x() + qy * w.y() + qz * w.z()),
      0.5 * (qw * w.x() + qy * w.z() - qz * w.y()), 0.5 * (qw * w.y() + qz * w.x() - qx * w.z()),
      0.5 * (qw * w.z() + qx * w.y() - qy * w.x());
  const Eigen::Vector3d l = m.cwiseProduct(w);
  d.w = l.cross(w).cwiseQuotient(m);  // Euler: I w' = (I w) x w
  return d;
}

State axpy(const State& s, double h, const State& d) { return {s.q + h * d.q, s.w + h * d.w}; }

}  // namespace

RigidBodyPosePredictor::RigidBodyPosePredictor(const Eigen::Vector3d& principal_moments,
                                               double step_s, int max_iterations)
    : moments_(principal_moments), step_s_(step_s), max_iterations_(max_iterations) {
  const auto& m = moments_;
  if (!m.allFinite() || m.minCoeff() <= 0.0)
    throw std::invalid_argument("RigidBodyPosePredictor: principal moments must be finite and > 0");
  const double tol = 1e-9 * m.sum();
  if (m[0] > m[1] + m[2] + tol || m[1] > m[0] + m[2] + tol || m[2] > m[0] + m[1] + tol)
    throw std::invalid_argument(
        "RigidBodyPosePredictor: principal moments break the triangle inequality (no real body)");
  if (!(step_s > 0.0)) throw std::invalid_argument("RigidBodyPosePredictor: step must be > 0 s");
  if (max_iterations < 1) throw std::invalid_argument("RigidBodyPosePredictor: iterations >= 1");
}

void RigidBodyPosePredictor::propagate(const Eigen::Vector3d& m, double step_s, double dt_s,
                                       Eigen::Quaterniond* q, Eigen::Vector3d* w) {
  if (dt_s == 0.0 || !std::isfinite(dt_s)) return;
  // A prediction stamped 1700 years ahead asked for 1e13 steps: the count
  // overflowed int (undefined) and the planner planned from it (fuzz target
  // rambo_planner). Longer spans than kMaxSteps steps are cut to them.
  const double max_span_s = step_s * kMaxSteps;
  dt_s = std::clamp(dt_s, -max_span_s, max_span_s);
  const int n = static_cast<int>(std::ceil(std::abs(dt_s) / step_s - 1e-9));
  const double h = dt_s / n;
  State s{Eigen::Vector4d(q->w(), q->x(), q->y(), q->z()), *w};
  for (int i = 0; i < n; ++i) {
    const State k1 = derivative(s, m);
    const State k2 = derivative(axpy(s, 0.5 * h, k1), m);
    const State k3 = derivative(axpy(s, 0.5 * h, k2), m);
    const State k4 = derivative(axpy(s, h, k3), m);
    s.q += h / 6.0 * (k1.q + 2.0 * k2.q + 2.0 * k3.q + k4.q);
    s.w += h / 6.0 * (k1.w + 2.0 * k2.w + 2.0 * k3.w + k4.w);
    s.q.normalize();
  }
  *q = Eigen::Quaterniond(s.q[0], s.q[1], s.q[2], s.q[3]);
  *w = s.w;
}

Eigen::VectorXd RigidBodyPosePredictor::residuals(const std::vector<PoseSample>& samples,
                                                  const Eigen::Quaterniond& q_ref,
                                                  const Eigen::Vector3d& w_ref) const {
  // Backwards from the last sample (t_ref) through every sample.
  const int n = static_cast<int>(samples.size());
  Eigen::VectorXd r(3 * n);
  Eigen::Quaterniond q = q_ref;
  Eigen::Vector3d w = w_ref;
  double t = t_ref_s_;
  for (int i = n - 1; i >= 0; --i) {
    const auto& s = samples[static_cast<std::size_t>(i)];
    propagate(moments_, step_s_, s.t_s - t, &q, &w);
    t = s.t_s;
    r.segment<3>(3 * i) = log_map(s.pose.linear().transpose() * q.toRotationMatrix());
  }
  return r;
}

bool RigidBodyPosePredictor::fit(const std::vector<PoseSample>& samples, std::string* why) {
  fitted_ = false;
  if (!check_samples(samples, 3, why)) return false;
  if (!translation_.fit(samples, why)) return false;
  const int n = static_cast<int>(samples.size());
  t_ref_s_ = samples.back().t_s;

  // Start: the last orientation, body rates from the last few differences.
  const Eigen::Quaterniond q0(samples.back().pose.linear());
  Eigen::Vector3d w0 = Eigen::Vector3d::Zero();
  const int pairs = std::min(n - 1, 4);
  for (int i = n - 1 - pairs; i < n - 1; ++i) {
    const auto& a = samples[static_cast<std::size_t>(i)];
    const auto& b = samples[static_cast<std::size_t>(i + 1)];
    w0 += log_map(a.pose.linear().transpose() * b.pose.linear()) / (b.t_s - a.t_s);
  }
  w0 /= pairs;

  // Levenberg-Marquardt on x = (delta, w): R_ref = R0 exp(delta).
  Eigen::Matrix<double, 6, 1> x;
  x << 0, 0, 0, w0;
  auto eval = [&](const Eigen::Matrix<double, 6, 1>& p) {
    return residuals(samples, q0 * exp_map(p.head<3>()), p.tail<3>());
  };
  Eigen::VectorXd r = eval(x);
  double cost = r.squaredNorm(), lambda = 1e-3;
  Eigen::MatrixXd jac(3 * n, 6);
  for (int it = 0; it < max_iterations_; ++it) {
    for (int k = 0; k < 6; ++k) {
      Eigen::Matrix<double, 6, 1> xp = x;
      const double eps = 1e-6;
      xp[k] += eps;
      jac.col(k) = (eval(xp) - r) / eps;
    }
    const Eigen::Matrix<double, 6, 6> jtj = jac.transpose() * jac;
    const Eigen::Matrix<double, 6, 1> jtr = jac.transpose() * r;
    bool improved = false;
    for (int tries = 0; tries < 10 && !improved; ++tries) {
      Eigen::Matrix<double, 6, 6> a = jtj;
      a.diagonal() += lambda * (jtj.diagonal().array() + 1e-12).matrix();
      const Eigen::Matrix<double, 6, 1> dx = -a.ldlt().solve(jtr);
      const Eigen::Matrix<double, 6, 1> xn = x + dx;
      const Eigen::VectorXd rn = eval(xn);
      if (rn.squaredNorm() < cost) {
        const double gain = cost - rn.squaredNorm();
        x = xn, r = rn, cost = rn.squaredNorm();
        lambda = std::max(lambda * 0.3, 1e-9);
        improved = true;
        if (dx.norm() < 1e-10 || gain < 1e-14 * (1.0 + cost)) it = max_iterations_;
      } else {
        lambda *= 10.0;
      }
    }
    if (!improved) break;
  }
  q_ref_ = (q0 * exp_map(x.head<3>())).normalized();
  w_ref_ = x.tail<3>();
  rms_residual_rad_ = std::sqrt(cost / n);
  const int dof = 3 * n - 6;
  if (dof > 0) {
    const double var = cost / dof;
    Eigen::Matrix<double, 6, 6> jtj = jac.transpose() * jac;
    const Eigen::Matrix<double, 6, 6> cov =
        var * jtj.ldlt().solve(Eigen::Matrix<double, 6, 6>::Identity());
    sigma_orientation_rad_ = std::sqrt(std::max(0.0, cov.topLeftCorner<3, 3>().trace()));
    sigma_rate_rad_s_ = std::sqrt(std::max(0.0, cov.bottomRightCorner<3, 3>().trace()));
  } else {
    sigma_orientation_rad_ = sigma_rate_rad_s_ = 0.0;
  }
  if (!q_ref_.coeffs().allFinite() || !w_ref_.allFinite()) {
    if (why) *why = "rigid-body fit did not converge to a finite state";
    return false;
  }
  fitted_ = true;
  return true;
}

PosePrediction RigidBodyPosePredictor::predict(double t_s) const {
  if (!fitted_) throw std::logic_error("RigidBodyPosePredictor: predict before a successful fit");
  const PosePrediction tr = translation_.predict(t_s);
  Eigen::Quaterniond q = q_ref_;
  Eigen::Vector3d w = w_ref_;
  propagate(moments_, step_s_, t_s - t_ref_s_, &q, &w);
  PosePrediction p;
  p.pose = Eigen::Isometry3d::Identity();
  p.pose.linear() = q.toRotationMatrix();
  p.pose.translation() = tr.pose.translation();
  p.position_sigma_mm = tr.position_sigma_mm;
  p.rotation_sigma_rad =
      std::hypot(sigma_orientation_rad_, sigma_rate_rad_s_ * std::abs(t_s - t_ref_s_));
  return p;
}

}  // namespace ephor::rambo
