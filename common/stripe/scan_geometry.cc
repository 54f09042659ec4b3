#include "common/stripe/scan_geometry.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace ephor::stripe {

namespace {
constexpr double kPi = std::numbers::pi;
}

std::optional<arm::Joints> StripeWorkcell::joints_for(const Eigen::Isometry3d& flange_in_table,
                                                      const arm::Joints& near,
                                                      const arm::Joints& zero_offset_rad) const {
  static const arm::Puma560 puma(0.0);
  const auto physical =
      puma.nearest_inverse(base_in_table.inverse() * flange_in_table, near + zero_offset_rad);
  if (!physical) return std::nullopt;
  return arm::Joints(*physical - zero_offset_rad);
}

arm::Joints StripeWorkcell::reference_joints() {
  // Upper arm forward and down a little, forearm down, wrist pointing down.
  return (arm::Joints() << 0.0, 0.3, -0.4, 0.0, kPi / 2 - 0.1, 0.0).finished();
}

Eigen::Vector3d StripeWorkcell::table_origin_in_field(const geometry::Workcell& cell) {
  return Eigen::Vector3d(cell.field_length_mm / 2.0, cell.field_width_mm / 2.0, 0.0);
}

StripeWorkcell StripeWorkcell::from_workcell(const geometry::Workcell& cell) {
  StripeWorkcell out;
  out.base_in_table =
      Eigen::Translation3d(Eigen::Vector3d(cell.base_x_mm, cell.base_y_mm, cell.base_z_mm) -
                           table_origin_in_field(cell)) *
      Eigen::AngleAxisd(cell.base_yaw_rad, Eigen::Vector3d::UnitZ());
  return out;
}

Eigen::Isometry3d projector_looking_down(double x_mm, double y_mm, double height_mm,
                                         double stripe_azimuth_rad) {
  const Eigen::Vector3d y(std::cos(stripe_azimuth_rad), std::sin(stripe_azimuth_rad), 0.0);
  const Eigen::Vector3d z(0.0, 0.0, -1.0);
  Eigen::Isometry3d s = Eigen::Isometry3d::Identity();
  s.linear().col(0) = y.cross(z);
  s.linear().col(1) = y;
  s.linear().col(2) = z;
  s.translation() = Eigen::Vector3d(x_mm, y_mm, height_mm);
  return s;
}

Eigen::Isometry3d projector_looking_at(const Eigen::Vector3d& target,
                                       const Eigen::Vector3d& approach, double distance_mm,
                                       const Eigen::Vector3d& stripe_hint) {
  const Eigen::Vector3d a = approach.normalized();
  return look_at(target + distance_mm * a, target, stripe_hint);
}

Eigen::Isometry3d flange_for_projector(const Eigen::Isometry3d& projector_pose,
                                       const SensorCalibration& cage) {
  return projector_pose * cage.projector_in_flange.inverse();
}

double joint_travel_s(const arm::Joints& from, const arm::Joints& to) {
  static const arm::JointLimits limits = arm::Puma560::default_limits();
  return ((to - from).cwiseAbs().array() / limits.qd_max.array()).maxCoeff();
}

std::vector<size_t> short_round(const std::vector<arm::Joints>& points, const arm::Joints& start) {
  const size_t n = points.size();
  std::vector<size_t> order;
  std::vector<bool> used(n, false);
  arm::Joints at = start;
  for (size_t k = 0; k < n; ++k) {
    size_t best = n;
    for (size_t i = 0; i < n; ++i)
      if (!used[i] &&
          (best == n || joint_travel_s(at, points[i]) < joint_travel_s(at, points[best])))
        best = i;
    used[best] = true;
    order.push_back(best);
    at = points[best];
  }
  // 2-opt on the closed round start -> order... -> start.
  auto p = [&](size_t k) -> const arm::Joints& {
    return k == 0 || k == n + 1 ? start : points[order[k - 1]];
  };
  for (bool better = true; better;) {
    better = false;
    for (size_t i = 1; i + 1 <= n; ++i)
      for (size_t j = i + 1; j <= n; ++j) {
        const double now = joint_travel_s(p(i - 1), p(i)) + joint_travel_s(p(j), p(j + 1));
        const double then = joint_travel_s(p(i - 1), p(j)) + joint_travel_s(p(i), p(j + 1));
        if (then < now - 1e-9) {
          std::reverse(order.begin() + static_cast<std::ptrdiff_t>(i - 1),
                       order.begin() + static_cast<std::ptrdiff_t>(j));
          better = true;
        }
      }
  }
  return order;
}

std::vector<std::pair<size_t, arm::Joints>> visiting_order(
    const StripeWorkcell& cell, const std::vector<Eigen::Isometry3d>& flanges_in_table,
    const arm::Joints& start, const arm::Joints& zero_offset_rad, bool least_travel) {
  std::vector<std::pair<size_t, arm::Joints>> out;
  arm::Joints near = start;
  if (!least_travel) {
    for (size_t i = 0; i < flanges_in_table.size(); ++i) {
      const auto q = cell.joints_for(flanges_in_table[i], near, zero_offset_rad);
      if (!q) continue;
      near = *q;
      out.emplace_back(i, *q);
    }
    return out;
  }
  // Each pose's readings from the start, a short round through them, then
  // the readings again each nearest the previous one.
  std::vector<size_t> reachable;
  std::vector<arm::Joints> first;
  for (size_t i = 0; i < flanges_in_table.size(); ++i)
    if (const auto q = cell.joints_for(flanges_in_table[i], start, zero_offset_rad)) {
      reachable.push_back(i);
      first.push_back(*q);
    }
  for (size_t k : short_round(first, start)) {
    const auto q = cell.joints_for(flanges_in_table[reachable[k]], near, zero_offset_rad);
    if (!q) continue;
    near = *q;
    out.emplace_back(reachable[k], *q);
  }
  return out;
}

std::vector<Eigen::Isometry3d> raster_projector_poses(const RasterSpec& spec) {
  if (!(spec.step_mm > 0.0) || !std::isfinite(spec.step_mm))
    throw std::invalid_argument("raster: step must be > 0 mm");
  if (!(spec.x1_mm > spec.x0_mm) || !(spec.y1_mm > spec.y0_mm))
    throw std::invalid_argument("raster: region must have x1 > x0 and y1 > y0");
  if (!(spec.pass_length_mm > 0.0)) throw std::invalid_argument("raster: pass length must be > 0");
  // "along" is the stripe's direction, "across" the stepping direction.
  const double a0 = spec.stripes_along_y ? spec.y0_mm : spec.x0_mm;
  const double a1 = spec.stripes_along_y ? spec.y1_mm : spec.x1_mm;
  const double c0 = spec.stripes_along_y ? spec.x0_mm : spec.y0_mm;
  const double c1 = spec.stripes_along_y ? spec.x1_mm : spec.y1_mm;
  const int passes =
      std::max(1, static_cast<int>(std::ceil((a1 - a0) / spec.pass_length_mm - 1e-9)));
  const int steps = static_cast<int>(std::floor((c1 - c0) / spec.step_mm + 1e-9)) + 1;
  const double azimuth = spec.stripes_along_y ? kPi / 2 : 0.0;
  std::vector<Eigen::Isometry3d> out;
  for (int p = 0; p < passes; ++p) {
    const double along = a0 + (a1 - a0) * (p + 0.5) / passes;
    for (int k = 0; k < steps; ++k) {
      const int kk = p % 2 == 0 ? k : steps - 1 - k;
      const double across = c0 + kk * spec.step_mm;
      const double x = spec.stripes_along_y ? across : along;
      const double y = spec.stripes_along_y ? along : across;
      out.push_back(projector_looking_down(x, y, spec.height_mm, azimuth));
    }
  }
  return out;
}

std::vector<Eigen::Isometry3d> sweep_projector_poses(const Eigen::Vector3d& target,
                                                     const Eigen::Vector3d& approach,
                                                     double distance_mm,
                                                     const Eigen::Vector3d& stripe_hint,
                                                     double half_width_mm, double step_mm) {
  if (!(step_mm > 0.0)) throw std::invalid_argument("sweep: step must be > 0 mm");
  const Eigen::Isometry3d centre = projector_looking_at(target, approach, distance_mm, stripe_hint);
  const Eigen::Vector3d across = centre.linear().col(0);
  const int n = static_cast<int>(std::floor(half_width_mm / step_mm + 1e-9));
  std::vector<Eigen::Isometry3d> out;
  for (int k = -n; k <= n; ++k) {
    Eigen::Isometry3d p = centre;
    p.translation() += k * step_mm * across;
    out.push_back(p);
  }
  return out;
}

}  // namespace ephor::stripe
