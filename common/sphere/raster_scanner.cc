#include "common/sphere/raster_scanner.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ephor::sphere {
namespace {
constexpr double kDegToRad = M_PI / 180.0;
}

RasterScanner::RasterScanner(const RasterScannerConfig& config) : config_(config) {
  if (!(config.azimuth_rate_deg_s > 0) || !(config.elevation_rate_deg_s > 0) ||
      !(config.pulse_rate_hz > 0) || !(config.half_extent_deg > 0) ||
      !(config.half_extent_deg < 80)) {
    throw std::invalid_argument(
        "RasterScanner: rates and half extent must be positive (extent < 80 deg)");
  }
}

double RasterScanner::line_duration_s() const {
  return 2.0 * config_.half_extent_deg / config_.azimuth_rate_deg_s;
}

double RasterScanner::frame_duration_s() const {
  return 2.0 * config_.half_extent_deg / config_.elevation_rate_deg_s;
}

double RasterScanner::azimuth_step_rad() const {
  return config_.azimuth_rate_deg_s / config_.pulse_rate_hz * kDegToRad;
}

ScanDirection RasterScanner::direction_at(double t_s) const {
  const double h = config_.half_extent_deg;
  const double line_s = line_duration_s();
  const double frame_s = frame_duration_s();
  ScanDirection d;
  d.line = static_cast<int64_t>(std::floor(t_s / line_s));
  const double in_line = t_s - static_cast<double>(d.line) * line_s;
  const double swept = std::min(config_.azimuth_rate_deg_s * in_line, 2.0 * h);
  // Even lines run left to right, odd lines back (instantaneous turn-around).
  const double az_deg = (d.line % 2 == 0) ? -h + swept : h - swept;
  const auto frame = static_cast<int64_t>(std::floor(t_s / frame_s));
  const double in_frame = t_s - static_cast<double>(frame) * frame_s;
  const double dropped = std::min(config_.elevation_rate_deg_s * in_frame, 2.0 * h);
  // Even frames run top to bottom, odd frames back up.
  const double el_deg = (frame % 2 == 0) ? h - dropped : -h + dropped;
  d.azimuth_rad = az_deg * kDegToRad;
  d.elevation_rad = el_deg * kDegToRad;
  return d;
}

double RasterScanner::required_half_extent_deg(const SphereTrajectory& trajectory, double t0_s,
                                               double t1_s, double margin, bool with_range_motion) {
  // Sample the interval finely: the extreme is at an end for linear motion,
  // but sampling keeps this right for any direction of motion.
  constexpr int kSamples = 200;
  const double z_fixed = trajectory.centre_at(0.5 * (t0_s + t1_s)).z();
  double worst = 0.0;
  for (int k = 0; k <= kSamples; ++k) {
    const double t = t0_s + (t1_s - t0_s) * k / kSamples;
    Eigen::Vector3d c = trajectory.centre_at(t);
    if (!with_range_motion) c.z() = z_fixed;
    // Azimuth: the sphere's silhouette seen in the X-Z plane.
    const double rho_xz = std::hypot(c.x(), c.z());
    const double half_az = std::asin(std::min(1.0, trajectory.radius_m / rho_xz));
    worst = std::max(worst, std::abs(std::atan2(c.x(), c.z())) + half_az);
    // Elevation: the sphere's silhouette seen from the azimuth plane.
    const double half_el = std::asin(std::min(1.0, trajectory.radius_m / c.norm()));
    worst = std::max(worst, std::abs(std::atan2(c.y(), rho_xz)) + half_el);
  }
  return margin * worst / kDegToRad;
}

SphereTrajectory SphereTrajectory::paper_trial(double distance_m, double t_pass_s) {
  SphereTrajectory s;
  const double v = table1_xy_speed_m_s(distance_m);
  s.t0_s = t_pass_s;
  s.position_at_t0_m = Eigen::Vector3d(0.0, 0.0, distance_m);
  s.velocity_m_s = Eigen::Vector3d(v, v, -kTable1ZSpeedMS);
  return s;
}

double table1_xy_speed_m_s(double distance_m) { return 0.006 * distance_m + 0.006 + 0.015; }

}  // namespace ephor::sphere
