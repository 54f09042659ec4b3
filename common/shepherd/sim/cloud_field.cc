#include "common/shepherd/sim/cloud_field.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>

namespace ephor::sim {

double Cloud::weight(const Eigen::Vector2d& p) const {
  const Eigen::Vector2d d = p - centre_px;
  const double c = std::cos(angle_rad), s = std::sin(angle_rad);
  const double du = (c * d.x() + s * d.y()) / semi_u_px;
  const double dv = (-s * d.x() + c * d.y()) / semi_v_px;
  const double r = std::sqrt(du * du + dv * dv);
  if (r >= 1.0) return 0.0;
  if (r <= core) return opacity;
  const double x = (1.0 - r) / (1.0 - core);  // 0 at the edge, 1 at the core
  return opacity * x * x * (3.0 - 2.0 * x);   // smoothstep: no visible rim
}

void validate(const CloudFieldConfig& c) {
  auto require = [](bool ok, const std::string& what) {
    if (!ok) throw std::invalid_argument("clouds: " + what);
  };
  require(c.clouds >= 0 && c.clouds <= 32, "clouds must be in [0, 32]");
  require(std::isfinite(c.min_semi_px) && c.min_semi_px > 0.0, "min_semi_px must be > 0");
  require(std::isfinite(c.max_semi_px) && c.max_semi_px >= c.min_semi_px,
          "max_semi_px must be >= min_semi_px");
  require(std::isfinite(c.min_speed_px_s) && c.min_speed_px_s >= 0.0,
          "min_speed_px_s must be >= 0");
  require(std::isfinite(c.max_speed_px_s) && c.max_speed_px_s >= c.min_speed_px_s,
          "max_speed_px_s must be >= min_speed_px_s");
  require(c.dark_level >= 0.0 && c.dark_level <= 255.0, "dark_level must be in [0, 255]");
  require(c.bright_level >= 0.0 && c.bright_level <= 255.0, "bright_level must be in [0, 255]");
}

CloudField::CloudField(const CloudFieldConfig& config, int width_px, int height_px)
    : width_px_(width_px), height_px_(height_px) {
  validate(config);
  std::mt19937_64 rng(config.seed ^ 0xc10dULL);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  auto between = [&](double a, double b) { return a + (b - a) * unit(rng); };
  for (int i = 0; i < config.clouds; ++i) {
    Cloud c;
    c.centre_px = {between(0.0, width_px), between(0.0, height_px)};
    c.semi_u_px = between(config.min_semi_px, config.max_semi_px);
    c.semi_v_px = between(config.min_semi_px, config.max_semi_px);
    c.angle_rad = between(0.0, std::numbers::pi);
    c.level = i % 2 == 0 ? config.dark_level : config.bright_level;
    start_.push_back(c);
    const double heading = between(0.0, 2.0 * std::numbers::pi);
    const double speed = between(config.min_speed_px_s, config.max_speed_px_s);
    velocity_px_s_.emplace_back(speed * std::cos(heading), speed * std::sin(heading));
  }
}

std::vector<Cloud> CloudField::at(double t_s) const {
  std::vector<Cloud> out = start_;
  for (size_t i = 0; i < out.size(); ++i) {
    // Wrap on a torus one cloud-diameter larger than the image on each side.
    const double margin = std::max(out[i].semi_u_px, out[i].semi_v_px);
    const double span_u = width_px_ + 2.0 * margin, span_v = height_px_ + 2.0 * margin;
    const Eigen::Vector2d p = start_[i].centre_px + velocity_px_s_[i] * t_s;
    auto wrap = [](double x, double lo, double span) {
      const double y = std::fmod(x - lo, span);
      return lo + (y < 0.0 ? y + span : y);
    };
    out[i].centre_px = {wrap(p.x(), -margin, span_u), wrap(p.y(), -margin, span_v)};
  }
  return out;
}

}  // namespace ephor::sim
