#include "common/rambo/polynomial_pose_predictor.h"

#include <cmath>
#include <numbers>
#include <stdexcept>

#include <Eigen/QR>

namespace ephor::rambo {

PolynomialPosePredictor::PolynomialPosePredictor(int degree, RotationCoordinates rotation)
    : degree_(degree), rotation_(rotation) {
  if (degree < 0 || degree > 5)
    throw std::invalid_argument("PolynomialPosePredictor: degree must be 0..5");
}

Eigen::VectorXd PolynomialMotion::basis(double t_s) const {
  Eigen::VectorXd phi(degree + 1);
  const double u = (t_s - t_mid_s) / t_scale_s;
  double p = 1.0;
  for (int k = 0; k <= degree; ++k, p *= u) phi[k] = p;
  return phi;
}

Eigen::Isometry3d PolynomialMotion::pose(double t_s) const {
  const Eigen::VectorXd phi = basis(t_s);
  Eigen::Vector3d xyz, ang;
  for (int c = 0; c < 3; ++c) {
    xyz[c] = phi.dot(coeff[static_cast<std::size_t>(c)]);
    ang[c] = phi.dot(coeff[static_cast<std::size_t>(c + 3)]);
  }
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  if (rotation == RotationCoordinates::kRotationVector) {
    const double a = ang.norm();
    p.linear() =
        a < 1e-12 ? r_mid : (r_mid * Eigen::AngleAxisd(a, ang / a).toRotationMatrix()).eval();
  } else {
    p.linear() = from_zyx_angles(ang);
  }
  p.translation() = xyz;
  return p;
}

bool PolynomialMotion::valid() const {
  if (degree < 0 || degree > 5 || !std::isfinite(t_mid_s) || !(t_scale_s > 0.0) ||
      !std::isfinite(t_scale_s) || !r_mid.allFinite() ||
      (r_mid.transpose() * r_mid - Eigen::Matrix3d::Identity()).norm() > 1e-6)
    return false;
  for (const Eigen::VectorXd& c : coeff)
    if (c.size() != degree + 1 || !c.allFinite()) return false;
  return true;
}

bool PolynomialPosePredictor::fit(const std::vector<PoseSample>& samples, std::string* why) {
  fitted_ = false;
  if (!check_samples(samples, static_cast<std::size_t>(degree_ + 1), why)) return false;
  const int n = static_cast<int>(samples.size());
  m_ = PolynomialMotion{};
  m_.degree = degree_;
  m_.rotation = rotation_;
  m_.t_mid_s = 0.5 * (samples.front().t_s + samples.back().t_s);
  m_.t_scale_s = std::max(0.5 * (samples.back().t_s - samples.front().t_s), 1e-6);
  Eigen::MatrixXd a(n, degree_ + 1);
  Eigen::MatrixXd y(n, 6);
  Eigen::Vector3d prev = Eigen::Vector3d::Zero();
  m_.r_mid = samples[static_cast<std::size_t>(n / 2)].pose.linear();
  for (int i = 0; i < n; ++i) {
    const auto& s = samples[static_cast<std::size_t>(i)];
    a.row(i) = m_.basis(s.t_s).transpose();
    Eigen::Vector3d ang;
    if (rotation_ == RotationCoordinates::kRotationVector) {
      const Eigen::AngleAxisd aa(m_.r_mid.transpose() * s.pose.linear());
      ang = aa.angle() * aa.axis();
    } else {
      ang = zyx_angles(s.pose.linear());
    }
    if (i > 0 &&
        rotation_ ==
            RotationCoordinates::kZyxAngles) {  // unwrap yaw and roll (pitch is in [-pi/2, pi/2])
      for (int k : {0, 2})
        ang[k] = prev[k] + std::remainder(ang[k] - prev[k], 2.0 * std::numbers::pi);
    }
    prev = ang;
    y.block<1, 3>(i, 0) = s.pose.translation().transpose();
    y.block<1, 3>(i, 3) = ang.transpose();
  }
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(a);
  if (qr.rank() < degree_ + 1) {
    if (why) *why = "pose sample times do not determine the polynomial";
    return false;
  }
  const int dof = n - (degree_ + 1);
  for (int c = 0; c < 6; ++c) {
    m_.coeff[static_cast<std::size_t>(c)] = qr.solve(y.col(c));
    const double rss = (a * m_.coeff[static_cast<std::size_t>(c)] - y.col(c)).squaredNorm();
    residual_var_[static_cast<std::size_t>(c)] = dof > 0 ? rss / dof : 0.0;
  }
  ata_inv_ = (a.transpose() * a).inverse();
  fitted_ = true;
  return true;
}

double PolynomialPosePredictor::coordinate(int c, double t_s, double* sigma) const {
  if (!fitted_) throw std::logic_error("PolynomialPosePredictor: predict before a successful fit");
  const Eigen::VectorXd phi = m_.basis(t_s);
  if (sigma)
    *sigma = std::sqrt(
        std::max(0.0, residual_var_[static_cast<std::size_t>(c)] * phi.dot(ata_inv_ * phi)));
  return phi.dot(m_.coeff[static_cast<std::size_t>(c)]);
}

PolynomialMotion PolynomialPosePredictor::motion() const {
  if (!fitted_) throw std::logic_error("PolynomialPosePredictor: motion before a successful fit");
  return m_;
}

PosePrediction PolynomialPosePredictor::predict(double t_s) const {
  if (!fitted_) throw std::logic_error("PolynomialPosePredictor: predict before a successful fit");
  PosePrediction p;
  Eigen::Vector3d sp, sr;
  for (int c = 0; c < 3; ++c) {
    coordinate(c, t_s, &sp[c]);
    coordinate(c + 3, t_s, &sr[c]);
  }
  p.pose = m_.pose(t_s);
  p.position_sigma_mm = sp.norm();
  p.rotation_sigma_rad = sr.norm();
  return p;
}

}  // namespace ephor::rambo
