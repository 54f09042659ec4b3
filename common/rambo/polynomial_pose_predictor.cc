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

Eigen::VectorXd PolynomialPosePredictor::basis(double t_s) const {
  Eigen::VectorXd phi(degree_ + 1);
  const double u = (t_s - t_ref_s_) / t_scale_s_;
  double p = 1.0;
  for (int k = 0; k <= degree_; ++k, p *= u) phi[k] = p;
  return phi;
}

bool PolynomialPosePredictor::fit(const std::vector<PoseSample>& samples, std::string* why) {
  fitted_ = false;
  if (!check_samples(samples, static_cast<std::size_t>(degree_ + 1), why)) return false;
  const int n = static_cast<int>(samples.size());
  t_ref_s_ = 0.5 * (samples.front().t_s + samples.back().t_s);
  t_scale_s_ = std::max(0.5 * (samples.back().t_s - samples.front().t_s), 1e-6);
  Eigen::MatrixXd a(n, degree_ + 1);
  Eigen::MatrixXd y(n, 6);
  Eigen::Vector3d prev = Eigen::Vector3d::Zero();
  r_mid_ = samples[static_cast<std::size_t>(n / 2)].pose.linear();
  for (int i = 0; i < n; ++i) {
    const auto& s = samples[static_cast<std::size_t>(i)];
    a.row(i) = basis(s.t_s).transpose();
    Eigen::Vector3d ang;
    if (rotation_ == RotationCoordinates::kRotationVector) {
      const Eigen::AngleAxisd aa(r_mid_.transpose() * s.pose.linear());
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
    coeff_[static_cast<std::size_t>(c)] = qr.solve(y.col(c));
    const double rss = (a * coeff_[static_cast<std::size_t>(c)] - y.col(c)).squaredNorm();
    residual_var_[static_cast<std::size_t>(c)] = dof > 0 ? rss / dof : 0.0;
  }
  ata_inv_ = (a.transpose() * a).inverse();
  fitted_ = true;
  return true;
}

double PolynomialPosePredictor::coordinate(int c, double t_s, double* sigma) const {
  if (!fitted_) throw std::logic_error("PolynomialPosePredictor: predict before a successful fit");
  const Eigen::VectorXd phi = basis(t_s);
  if (sigma)
    *sigma = std::sqrt(
        std::max(0.0, residual_var_[static_cast<std::size_t>(c)] * phi.dot(ata_inv_ * phi)));
  return phi.dot(coeff_[static_cast<std::size_t>(c)]);
}

PosePrediction PolynomialPosePredictor::predict(double t_s) const {
  PosePrediction p;
  Eigen::Vector3d xyz, ypr, sp, sr;
  for (int c = 0; c < 3; ++c) {
    xyz[c] = coordinate(c, t_s, &sp[c]);
    ypr[c] = coordinate(c + 3, t_s, &sr[c]);
  }
  p.pose = Eigen::Isometry3d::Identity();
  if (rotation_ == RotationCoordinates::kRotationVector) {
    const double a = ypr.norm();
    p.pose.linear() =
        a < 1e-12 ? r_mid_ : (r_mid_ * Eigen::AngleAxisd(a, ypr / a).toRotationMatrix()).eval();
  } else {
    p.pose.linear() = from_zyx_angles(ypr);
  }
  p.pose.translation() = xyz;
  p.position_sigma_mm = sp.norm();
  p.rotation_sigma_rad = sr.norm();
  return p;
}

}  // namespace ephor::rambo
