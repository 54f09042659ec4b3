#include "common/arm/puma560.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace ephor::arm {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

// One standard DH transform: Rz(theta) Tz(d) Tx(a) Rx(alpha).
Eigen::Isometry3d dh_transform(double theta, const DhLink& l) {
  const double ct = std::cos(theta), st = std::sin(theta);
  const double ca = std::cos(l.alpha_rad), sa = std::sin(l.alpha_rad);
  Eigen::Matrix4d m;
  m << ct, -st * ca, st * sa, l.a_mm * ct,  //
      st, ct * ca, -ct * sa, l.a_mm * st,   //
      0.0, sa, ca, l.d_mm,                  //
      0.0, 0.0, 0.0, 1.0;
  return Eigen::Isometry3d(m);
}

double angle_diff(double a, double b) { return std::remainder(a - b, 2.0 * kPi); }

}  // namespace

bool JointLimits::within(const Joints& q, double tolerance_rad) const {
  for (int i = 0; i < 6; ++i) {
    if (!std::isfinite(q[i]) || q[i] < q_min[i] - tolerance_rad || q[i] > q_max[i] + tolerance_rad)
      return false;
  }
  return true;
}

std::optional<double> wrap_into(double angle, double lo, double hi, double reference) {
  if (!std::isfinite(angle)) return std::nullopt;
  // Start from the representation nearest the reference, then try neighbours.
  const double base = reference + angle_diff(angle, reference);
  std::optional<double> best;
  for (int k = -2; k <= 2; ++k) {
    const double c = base + 2.0 * kPi * k;
    if (c < lo - 1e-9 || c > hi + 1e-9) continue;
    if (!best || std::abs(c - reference) < std::abs(*best - reference)) best = c;
  }
  if (best) best = std::clamp(*best, lo, hi);
  return best;
}

Puma560::Puma560(double tool_length_mm, JointLimits limits)
    : tool_length_mm_(tool_length_mm), limits_(std::move(limits)) {
  if (!std::isfinite(tool_length_mm) || tool_length_mm < 0.0)
    throw std::invalid_argument("Puma560: tool length must be finite and >= 0 mm");
}

JointLimits Puma560::default_limits() {
  JointLimits l;
  l.q_min << -160 * kDeg, -45 * kDeg, -225 * kDeg, -110 * kDeg, -100 * kDeg, -266 * kDeg;
  l.q_max << 160 * kDeg, 225 * kDeg, 45 * kDeg, 170 * kDeg, 100 * kDeg, 266 * kDeg;
  l.qd_max << 1.0, 1.0, 1.0, 2.0, 2.0, 2.0;
  l.qdd_max << 2.0, 2.0, 2.0, 4.0, 4.0, 4.0;
  return l;
}

const std::array<DhLink, 6>& Puma560::dh() {
  static const std::array<DhLink, 6> links{{{0.0, 0.0, kPi / 2},
                                            {0.0, kA2Mm, 0.0},
                                            {kD3Mm, kA3Mm, -kPi / 2},
                                            {kD4Mm, 0.0, kPi / 2},
                                            {0.0, 0.0, -kPi / 2},
                                            {0.0, 0.0, 0.0}}};
  return links;
}

Joints Puma560::qz() { return Joints::Zero(); }
Joints Puma560::qr() { return (Joints() << 0, kPi / 2, -kPi / 2, 0, 0, 0).finished(); }
Joints Puma560::qs() { return (Joints() << 0, 0, -kPi / 2, 0, 0, 0).finished(); }
Joints Puma560::qn() { return (Joints() << 0, kPi / 4, kPi, 0, kPi / 4, 0).finished(); }

std::array<Eigen::Isometry3d, 7> Puma560::link_frames(const Joints& q) const {
  std::array<Eigen::Isometry3d, 7> frames;
  frames[0] = Eigen::Isometry3d::Identity();
  for (int i = 0; i < 6; ++i) frames[i + 1] = frames[i] * dh_transform(q[i], dh()[i]);
  return frames;
}

Eigen::Isometry3d Puma560::flange(const Joints& q) const { return link_frames(q)[6]; }

Eigen::Isometry3d Puma560::forward(const Joints& q) const {
  return flange(q) * Eigen::Translation3d(0.0, 0.0, tool_length_mm_);
}

std::vector<Joints> Puma560::raw_inverse(const Eigen::Isometry3d& tool_pose) const {
  std::vector<Joints> out;
  const Eigen::Matrix3d r = tool_pose.linear();
  const Eigen::Vector3d p = tool_pose.translation() - tool_length_mm_ * r.col(2);  // wrist centre
  if (!p.allFinite() || !r.allFinite()) return out;

  // Wrist centre in terms of q1..q3 (derived from the DH chain):
  //   px = c1 x1 + s1 d3,  py = s1 x1 - c1 d3,  pz = y1
  //   x1 = a2 c2 + a3 c23 - d4 s23,  y1 = a2 s2 + a3 s23 + d4 c23
  constexpr double kTol = 1e-9;
  const double r2 = p.x() * p.x() + p.y() * p.y();
  double x1_sq = r2 - kD3Mm * kD3Mm;
  if (x1_sq < -kTol * kD3Mm * kD3Mm - 1e-9) return out;  // inside the column's offset cylinder
  x1_sq = std::max(0.0, x1_sq);
  const double l3 = std::hypot(kA3Mm, kD4Mm);
  const double phi = std::atan2(kD4Mm, kA3Mm);

  for (int shoulder : {+1, -1}) {
    const double x1 = shoulder * std::sqrt(x1_sq);
    // (px + i py) = (c1 + i s1)(x1 - i d3)
    const double q1 = std::atan2(p.y(), p.x()) - std::atan2(-kD3Mm, x1);
    const double k = (x1 * x1 + p.z() * p.z() - kA2Mm * kA2Mm - l3 * l3) / (2.0 * kA2Mm);
    double cos_arg = k / l3;
    if (std::abs(cos_arg) > 1.0 + 1e-9) continue;  // out of reach
    cos_arg = std::clamp(cos_arg, -1.0, 1.0);
    for (int elbow : {+1, -1}) {
      // a3 c3 - d4 s3 = l3 cos(q3 + phi) = k
      const double q3 = -phi + elbow * std::acos(cos_arg);
      const double c3 = std::cos(q3), s3 = std::sin(q3);
      const double u = kA2Mm + kA3Mm * c3 - kD4Mm * s3;
      const double w = kA3Mm * s3 + kD4Mm * c3;
      const double q2 = std::atan2(p.z(), x1) - std::atan2(w, u);

      Joints q;
      q << q1, q2, q3, 0.0, 0.0, 0.0;
      const Eigen::Matrix3d r03 = link_frames(q)[3].linear();
      // R36 = Rz(q4) Ry(-q5) Rz(q6) for this DH convention.
      const Eigen::Matrix3d r36 = r03.transpose() * r;
      const double c5 = std::clamp(r36(2, 2), -1.0, 1.0);
      const double s5_abs = std::hypot(r36(0, 2), r36(1, 2));
      if (s5_abs < 1e-9) {
        // Wrist singularity: only q4 + q6 (c5 = 1) or q6 - q4 (c5 = -1) is defined.
        const double q5 = c5 > 0.0 ? 0.0 : kPi;
        // c5 = 1: R36 = Rz(q4 + q6); c5 = -1: R36 = Ry(pi) Rz(q6 - q4). Put it all in q6.
        q[3] = 0.0;
        q[4] = q5;
        q[5] = c5 > 0.0 ? std::atan2(r36(1, 0), r36(0, 0)) : std::atan2(r36(1, 0), -r36(0, 0));
        out.push_back(q);
        continue;
      }
      for (int wrist : {+1, -1}) {
        const double s5 = wrist * s5_abs;
        q[3] = std::atan2(-r36(1, 2) / s5, -r36(0, 2) / s5);
        q[4] = std::atan2(s5, c5);
        q[5] = std::atan2(-r36(2, 1) / s5, r36(2, 0) / s5);
        out.push_back(q);
      }
    }
  }
  return out;
}

std::vector<Joints> Puma560::inverse(const Eigen::Isometry3d& tool_pose) const {
  std::vector<Joints> out;
  for (const Joints& raw : raw_inverse(tool_pose)) {
    Joints q;
    bool ok = true;
    for (int i = 0; i < 6 && ok; ++i) {
      const auto w = wrap_into(raw[i], limits_.q_min[i], limits_.q_max[i], 0.0);
      if (!w)
        ok = false;
      else
        q[i] = *w;
    }
    if (ok) out.push_back(q);
  }
  return out;
}

std::optional<Joints> Puma560::nearest_inverse(const Eigen::Isometry3d& tool_pose,
                                               const Joints& current) const {
  std::optional<Joints> best;
  double best_cost = 0.0;
  for (const Joints& raw : raw_inverse(tool_pose)) {
    Joints q;
    bool ok = true;
    for (int i = 0; i < 6 && ok; ++i) {
      const auto w = wrap_into(raw[i], limits_.q_min[i], limits_.q_max[i], current[i]);
      if (!w)
        ok = false;
      else
        q[i] = *w;
    }
    if (!ok) continue;
    // Time-like cost: the slowest joint's travel, then the total as a tie-break.
    const Joints travel = ((q - current).array().abs() / limits_.qd_max.array()).matrix();
    const double cost = travel.maxCoeff() + 1e-3 * travel.sum();
    if (!best || cost < best_cost) {
      best = q;
      best_cost = cost;
    }
  }
  return best;
}

}  // namespace ephor::arm
