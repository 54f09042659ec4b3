#include "procs/shepherd/planner/bounce_predictor.h"

#include <cmath>
#include <limits>

namespace ephor::planner {
namespace {

struct Body {
  double x, y, vx, vy, speed;
  bool moving;
};

// How far a body reaches from its centre along the unit vector (nx, ny).
double extent(const Body& b, double hl, double hw, double nx, double ny) {
  if (!b.moving) return hw;  // heading unknown: its narrow side
  const double fx = b.vx / b.speed, fy = b.vy / b.speed;
  return hl * std::abs(fx * nx + fy * ny) + hw * std::abs(-fy * nx + fx * ny);
}

// World::bounce: reflected about the normal into the obstacle, unless grazing.
void reflect(Body& b, double nx, double ny) {
  if (!b.moving) return;
  const double approach = (b.vx * nx + b.vy * ny) / b.speed;
  if (approach <= 0.05) return;
  const double along = b.vx * nx + b.vy * ny;
  b.vx -= 2.0 * along * nx;
  b.vy -= 2.0 * along * ny;
}

double straight_exit_s(const Body& b, double length, double width) {
  const double inf = std::numeric_limits<double>::infinity();
  if (!b.moving) return inf;
  const auto axis = [inf](double p, double v, double hi) {
    if (v > 0.0) return (hi - p) / v;
    if (v < 0.0) return -p / v;
    return inf;
  };
  return std::min(axis(b.x, b.vx, length), axis(b.y, b.vy, width));
}

}  // namespace

std::vector<double> BouncePredictor::exit_times_s(const std::vector<Sheep>& sheep) const {
  const double inf = std::numeric_limits<double>::infinity();
  const auto& w = config_.workcell;
  const double hl = config_.sheep_half_length_mm, hw = config_.sheep_half_width_mm;
  std::vector<double> exit(sheep.size(), inf);
  std::vector<Body> bodies;
  std::vector<size_t> index;  // bodies[k] is sheep[index[k]]
  for (size_t i = 0; i < sheep.size(); ++i) {
    const Sheep& s = sheep[i];
    if (s.state == SheepState::kDead || !std::isfinite(s.x_mm) || !std::isfinite(s.y_mm) ||
        !std::isfinite(s.vx_mm_s) || !std::isfinite(s.vy_mm_s)) {
      continue;
    }
    if (!w.inside_field(s.x_mm, s.y_mm)) {
      exit[i] = 0.0;
      continue;
    }
    const double speed = std::hypot(s.vx_mm_s, s.vy_mm_s);
    const bool moving = speed >= config_.min_speed_mm_s;
    bodies.push_back({s.x_mm, s.y_mm, moving ? s.vx_mm_s : 0.0, moving ? s.vy_mm_s : 0.0,
                      moving ? speed : 0.0, moving});
    index.push_back(i);
  }
  std::vector<bool> gone(bodies.size(), false);
  const int steps = static_cast<int>(std::ceil(config_.horizon_s / config_.step_s));
  for (int k = 1; k <= steps; ++k) {
    const double t = k * config_.step_s;
    for (size_t a = 0; a < bodies.size(); ++a) {
      if (gone[a]) continue;
      Body& b = bodies[a];
      b.x += b.vx * config_.step_s;
      b.y += b.vy * config_.step_s;
      if (!w.inside_field(b.x, b.y)) {
        exit[index[a]] = t;
        gone[a] = true;
      }
    }
    for (size_t a = 0; a < bodies.size(); ++a) {
      if (gone[a]) continue;
      Body& b = bodies[a];
      if (config_.pedestal) {
        const double dx = w.base_x_mm - b.x, dy = w.base_y_mm - b.y;
        const double d = std::hypot(dx, dy);
        if (d > 1e-9 && d <= w.pedestal_radius_mm + extent(b, hl, hw, dx / d, dy / d)) {
          reflect(b, dx / d, dy / d);
        }
      }
      if (!config_.sheep) continue;
      for (size_t c = a + 1; c < bodies.size(); ++c) {
        if (gone[c]) continue;
        Body& o = bodies[c];
        const double dx = o.x - b.x, dy = o.y - b.y;
        const double d = std::hypot(dx, dy);
        if (d < 1e-9) continue;
        const double nx = dx / d, ny = dy / d;
        if (d > extent(b, hl, hw, nx, ny) + extent(o, hl, hw, nx, ny)) continue;
        reflect(b, nx, ny);
        reflect(o, -nx, -ny);
      }
    }
  }
  const double stepped_s = steps * config_.step_s;
  for (size_t a = 0; a < bodies.size(); ++a) {
    if (!gone[a]) {
      exit[index[a]] = stepped_s + straight_exit_s(bodies[a], w.field_length_mm, w.field_width_mm);
    }
  }
  return exit;
}

}  // namespace ephor::planner
