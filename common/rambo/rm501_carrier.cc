#include "common/rambo/rm501_carrier.h"

#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

namespace ephor::rambo {
namespace {

constexpr double kDeg = M_PI / 180.0;

}  // namespace

Rm501Carrier::Joints Rm501Carrier::lower_limits() {
  Joints q;
  q << -150.0, -30.0, -90.0, -90.0, -180.0;
  return q * kDeg;
}

Rm501Carrier::Joints Rm501Carrier::upper_limits() {
  Joints q;
  q << 150.0, 100.0, 0.0, 90.0, 180.0;
  return q * kDeg;
}

Rm501Carrier::Joints Rm501Carrier::max_speeds() {
  Joints w;
  w << 120.0, 72.0, 109.0, 100.0, 163.0;
  return w * kDeg;
}

Eigen::Isometry3d Rm501Carrier::flange_in_arm(const Joints& q) {
  const double phi2 = q[1], phi3 = q[1] + q[2], phi4 = q[1] + q[2] + q[3];
  const double r =
      kUpperArmMm * std::cos(phi2) + kForearmMm * std::cos(phi3) + kHandMm * std::cos(phi4);
  const double z = kShoulderHeightMm + kUpperArmMm * std::sin(phi2) + kForearmMm * std::sin(phi3) +
                   kHandMm * std::sin(phi4);
  Eigen::Isometry3d f = Eigen::Isometry3d::Identity();
  f.linear() = (Eigen::AngleAxisd(q[0], Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(-phi4, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(q[4], Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  f.translation() << r * std::cos(q[0]), r * std::sin(q[0]), z;
  return f;
}

std::array<Eigen::Vector3d, 5> Rm501Carrier::chain_in_arm(const Joints& q) {
  const double phi2 = q[1], phi3 = q[1] + q[2], phi4 = q[1] + q[2] + q[3];
  const Eigen::Vector3d out(std::cos(q[0]), std::sin(q[0]), 0.0);  // the waist's heading
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  std::array<Eigen::Vector3d, 5> p;
  p[0] = Eigen::Vector3d::Zero();
  p[1] = kShoulderHeightMm * up;
  p[2] = p[1] + kUpperArmMm * (std::cos(phi2) * out + std::sin(phi2) * up);
  p[3] = p[2] + kForearmMm * (std::cos(phi3) * out + std::sin(phi3) * up);
  p[4] = p[3] + kHandMm * (std::cos(phi4) * out + std::sin(phi4) * up);
  return p;
}

std::array<Eigen::Vector3d, 6> Rm501Carrier::chain(double t_s) const {
  const std::array<Eigen::Vector3d, 5> a = chain_in_arm(joints(t_s));
  std::array<Eigen::Vector3d, 6> p;
  for (std::size_t k = 0; k < a.size(); ++k) p[k] = arm_in_base_ * a[k];
  p[5] = pose(t_s).translation();
  return p;
}

Rm501Carrier::Rm501Carrier(const Eigen::Isometry3d& target_pose0, std::uint64_t seed,
                           double speed_scale) {
  if (!(speed_scale > 0.0) || !std::isfinite(speed_scale))
    throw std::invalid_argument("RM-501 carrier: speed scale must be > 0, not " +
                                std::to_string(speed_scale));
  // Upper arm 60 deg up, forearm and hand level: the target in front of it.
  nominal_ << 0.0, 60.0 * kDeg, -60.0 * kDeg, 0.0, 0.0;
  amplitude_ << 5.0 * kDeg, 4.0 * kDeg, 5.0 * kDeg, 8.0 * kDeg, 60.0 * kDeg;
  Joints base_omega;
  base_omega << 0.15, 0.11, 0.13, 0.20, 0.067;      // rad/s at speed_scale 1
  std::mt19937_64 rng(seed ^ 0x52'4d'35'30'31ULL);  // "RM501": apart from the tumble's draws
  std::uniform_real_distribution<double> jitter(0.8, 1.2), angle(-M_PI, M_PI);
  for (int i = 0; i < 5; ++i) {
    omega_[i] = base_omega[i] * jitter(rng) * speed_scale;
    phase_[i] = angle(rng);
    const double lo = nominal_[i] - amplitude_[i], hi = nominal_[i] + amplitude_[i];
    if (lo < lower_limits()[i] || hi > upper_limits()[i])
      throw std::invalid_argument("RM-501 carrier: joint " + std::to_string(i + 1) +
                                  " would leave its limits");
    if (amplitude_[i] * omega_[i] > max_speeds()[i])
      throw std::invalid_argument("RM-501 carrier: joint " + std::to_string(i + 1) +
                                  " would turn at " +
                                  std::to_string(amplitude_[i] * omega_[i] / kDeg) +
                                  " deg/s, beyond its " + std::to_string(max_speeds()[i] / kDeg) +
                                  " deg/s (speed scale " + std::to_string(speed_scale) + ")");
  }
  // The arm turned to face the PUMA (its x along the PUMA's -x) and placed so
  // that at the nominal joints the target is at target_pose0.
  const Eigen::Matrix3d facing =
      Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Isometry3d f0 = flange_in_arm(nominal_);
  target_in_flange_.linear() = (facing * f0.linear()).transpose() * target_pose0.linear();
  target_in_flange_.translation() = Eigen::Vector3d(kMountMm, 0.0, 0.0);
  arm_in_base_.linear() = facing;
  arm_in_base_.translation() =
      target_pose0.translation() - facing * (f0 * target_in_flange_.translation());
}

Rm501Carrier::Joints Rm501Carrier::joints(double t_s) const {
  Joints q;
  for (int i = 0; i < 5; ++i)
    q[i] = nominal_[i] + amplitude_[i] * std::sin(omega_[i] * t_s + phase_[i]);
  return q;
}

Rm501Carrier::Joints Rm501Carrier::joint_rates(double t_s) const {
  Joints w;
  for (int i = 0; i < 5; ++i)
    w[i] = amplitude_[i] * omega_[i] * std::cos(omega_[i] * t_s + phase_[i]);
  return w;
}

Eigen::Isometry3d Rm501Carrier::pose(double t_s) const {
  return arm_in_base_ * flange_in_arm(joints(t_s)) * target_in_flange_;
}

Eigen::Vector3d Rm501Carrier::body_rates(double t_s) const {
  constexpr double h = 0.0005;
  const Eigen::Matrix3d r0 = pose(t_s - h).linear(), r1 = pose(t_s + h).linear();
  const Eigen::AngleAxisd d(r0.transpose() * r1);
  return d.axis() * d.angle() / (2.0 * h);
}

}  // namespace ephor::rambo
