#include "common/stripe/scan_geometry.h"

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
