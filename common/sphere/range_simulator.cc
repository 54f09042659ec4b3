#include "common/sphere/range_simulator.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ephor::sphere {

std::optional<double> ray_sphere_range(const Eigen::Vector3d& origin,
                                       const Eigen::Vector3d& direction,
                                       const Eigen::Vector3d& centre, double radius_m) {
  // |o + r d - c|^2 = R^2 with |d| = 1: r^2 + 2 b r + c0 = 0.
  const Eigen::Vector3d oc = origin - centre;
  const double b = direction.dot(oc);
  const double c0 = oc.squaredNorm() - radius_m * radius_m;
  const double disc = b * b - c0;
  if (disc < 0.0) return std::nullopt;
  const double root = std::sqrt(disc);
  const double near = -b - root;
  if (near >= 0.0) return near;
  const double far = -b + root;
  if (far >= 0.0) return far;  // origin inside the sphere
  return std::nullopt;
}

RangeSimulator::RangeSimulator(const RangeSimulatorConfig& config)
    : config_(config), scanner_(config.scanner), rng_(config.seed) {
  if (!(config.noise.range_sigma_m >= 0) || !(config.noise.angle_sigma_rad >= 0)) {
    throw std::invalid_argument("RangeSimulator: noise sigmas must be >= 0");
  }
}

std::vector<ScanLine> RangeSimulator::scan(double t_begin_s, double duration_s,
                                           int64_t first_line_id) {
  std::normal_distribution<double> unit(0.0, 1.0);
  const RangeNoise& noise = config_.noise;
  const double wall_below_rad = config_.background.below_elevation_deg * M_PI / 180.0;
  std::vector<ScanLine> lines;
  // Pulse times on the global pulse clock so that windows of consecutive
  // trials tile time exactly: pulse k at k / rate.
  const double rate = config_.scanner.pulse_rate_hz;
  const auto k0 = static_cast<int64_t>(std::ceil(t_begin_s * rate - 1e-9));
  const auto k1 = static_cast<int64_t>(std::ceil((t_begin_s + duration_s) * rate - 1e-9));
  for (int64_t k = k0; k < k1; ++k) {
    const double t = static_cast<double>(k) / rate;
    // The first pulse can fall a rounding error before t_begin_s (a window
    // start 3 * 0.1 s is 0.30000000000000004, its pulse 0.3): it is the
    // raster's first, not one of a line before it (whose id the previous
    // window's last line has).
    const ScanDirection dir = scanner_.direction_at(std::max(0.0, t - t_begin_s));
    const int64_t id = first_line_id + dir.line;
    if (lines.empty() || lines.back().id != id) lines.push_back(ScanLine{id, {}});
    const Eigen::Vector3d ray = ray_direction(dir.azimuth_rad, dir.elevation_rad);
    std::optional<double> range = ray_sphere_range(
        Eigen::Vector3d::Zero(), ray, config_.sphere.centre_at(t), config_.sphere.radius_m);
    if (!range && config_.background.enabled && dir.elevation_rad < wall_below_rad) {
      range = config_.background.range_m;
    }
    Pulse p;
    p.t_s = t;
    p.azimuth_rad = dir.azimuth_rad + noise.angle_sigma_rad * unit(rng_);
    p.elevation_rad = dir.elevation_rad + noise.angle_sigma_rad * unit(rng_);
    p.range_m = range ? *range + noise.range_sigma_m * unit(rng_) : std::nan("");
    lines.back().pulses.push_back(p);
  }
  return lines;
}

RangeSimulatorConfig RangeSimulator::paper_trial(double distance_m, uint64_t seed, double t_begin_s,
                                                 double duration_s) {
  if (!(distance_m > 2.0 * kSphereRadiusM)) {
    throw std::invalid_argument("paper_trial: distance must exceed the sphere's diameter");
  }
  RangeSimulatorConfig c;
  c.sphere = SphereTrajectory::paper_trial(distance_m, t_begin_s + 0.5 * duration_s);
  c.scanner.half_extent_deg =
      RasterScanner::required_half_extent_deg(c.sphere, t_begin_s, t_begin_s + duration_s);
  c.seed = seed;
  return c;
}

}  // namespace ephor::sphere
