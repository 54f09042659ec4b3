#include "common/stripe/true_arm.h"

#include <cmath>
#include <numbers>
#include <random>

namespace ephor::stripe {

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;
}

ArmErrors ArmErrors::draw(std::uint64_t seed, double max_zero_deg, double link_mm,
                          double twist_deg) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  ArmErrors e;
  for (int j = 1; j < 6; ++j) e.zero_offset_rad[j] = max_zero_deg * kDeg * unit(rng);
  for (auto& l : e.dh_error) {
    l.d_mm = link_mm * unit(rng);
    l.a_mm = link_mm * unit(rng);
    l.alpha_rad = twist_deg * kDeg * unit(rng);
  }
  return e;
}

TrueArm::TrueArm(ArmErrors errors) : errors_(errors) {
  const auto& nominal = arm::Puma560::dh();
  for (int i = 0; i < 6; ++i) {
    dh_[i].d_mm = nominal[i].d_mm + errors_.dh_error[i].d_mm;
    dh_[i].a_mm = nominal[i].a_mm + errors_.dh_error[i].a_mm;
    dh_[i].alpha_rad = nominal[i].alpha_rad + errors_.dh_error[i].alpha_rad;
  }
}

TrueArm TrueArm::with_zero_offsets(const arm::Joints& zero_offset_rad) {
  ArmErrors e;
  e.zero_offset_rad = zero_offset_rad;
  return TrueArm(e);
}

Eigen::Isometry3d TrueArm::flange(const arm::Joints& q) const {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  for (int i = 0; i < 6; ++i) {
    // Standard DH: Rz(theta) Tz(d) Tx(a) Rx(alpha), as common/arm/puma560.cc.
    const double theta = q[i] + errors_.zero_offset_rad[i];
    const double ct = std::cos(theta), st = std::sin(theta);
    const double ca = std::cos(dh_[i].alpha_rad), sa = std::sin(dh_[i].alpha_rad);
    Eigen::Matrix4d m;
    m << ct, -st * ca, st * sa, dh_[i].a_mm * ct,  //
        st, ct * ca, -ct * sa, dh_[i].a_mm * st,   //
        0.0, sa, ca, dh_[i].d_mm,                  //
        0.0, 0.0, 0.0, 1.0;
    t = t * Eigen::Isometry3d(m);
  }
  return t;
}

}  // namespace ephor::stripe
