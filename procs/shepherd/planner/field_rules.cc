#include "procs/shepherd/planner/field_rules.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace ephor::planner {

bool finite_sheep(const Sheep& s) {
  return std::isfinite(s.x_mm) && std::isfinite(s.y_mm) && std::isfinite(s.vx_mm_s) &&
         std::isfinite(s.vy_mm_s);
}

double FieldRules::time_to_boundary(const Sheep& s) const {
  const double inf = std::numeric_limits<double>::infinity();
  if (!config_.workcell.inside_field(s.x_mm, s.y_mm)) return 0.0;
  if (std::hypot(s.vx_mm_s, s.vy_mm_s) < config_.min_sheep_speed_mm_s) return inf;
  return straight_time_to_edge_s(s);
}

bool FieldRules::heading_to_centre(const Sheep& s) const {
  const double speed = std::hypot(s.vx_mm_s, s.vy_mm_s);
  const double cx = centre_x_mm() - s.x_mm;
  const double cy = centre_y_mm() - s.y_mm;
  const double dist = std::hypot(cx, cy);
  if (speed < config_.min_sheep_speed_mm_s || dist < 1e-6) return false;
  const double cos_angle = (s.vx_mm_s * cx + s.vy_mm_s * cy) / (speed * dist);
  return cos_angle >= std::cos(config_.heading_to_centre_rad);
}

bool FieldRules::needs_saving(const Sheep& s) const { return needs_saving(s, time_to_boundary(s)); }

bool FieldRules::needs_saving(const Sheep& s, double leaves_in_s) const {
  if (s.state == SheepState::kDead || !finite_sheep(s)) return false;
  if (heading_to_centre(s)) return false;
  if (std::hypot(s.x_mm - centre_x_mm(), s.y_mm - centre_y_mm()) < config_.centre_zone_mm) {
    return false;
  }
  return std::isfinite(leaves_in_s) && leaves_in_s <= config_.save_horizon_s;
}

std::vector<int> FieldRules::candidates_by_urgency(const std::vector<Sheep>& sheep) const {
  std::vector<int> out;
  std::vector<double> t(sheep.size());
  if (config_.predict_bounces) {
    t = bounces_.exit_times_s(sheep);
  } else {
    for (size_t i = 0; i < sheep.size(); ++i) t[i] = time_to_boundary(sheep[i]);
  }
  for (size_t i = 0; i < sheep.size(); ++i) {
    if (needs_saving(sheep[i], t[i])) out.push_back(static_cast<int>(i));
  }
  std::stable_sort(out.begin(), out.end(), [&t, &sheep](int a, int b) {
    const auto ia = static_cast<size_t>(a);
    const auto ib = static_cast<size_t>(b);
    if (t[ia] != t[ib]) return t[ia] < t[ib];
    return sheep[ia].id < sheep[ib].id;  // deterministic tie-break
  });
  return out;
}

double FieldRules::redirect_heading(double x_mm, double y_mm, const std::vector<Sheep>& sheep,
                                    int target_id) const {
  const double to_centre = std::atan2(centre_y_mm() - y_mm, centre_x_mm() - x_mm);
  const double clearance = config_.redirect_clearance_mm;
  if (!(clearance > 0.0) || !(config_.redirect_max_rad > 0.0)) return to_centre;
  double speed = 0.0;
  for (const Sheep& s : sheep) {
    if (s.id == target_id && finite_sheep(s)) speed = std::hypot(s.vx_mm_s, s.vy_mm_s);
  }
  if (speed < config_.min_sheep_speed_mm_s) speed = config_.redirect_nominal_speed_mm_s;
  // Candidate headings fanned around the centre's direction; the one along
  // which the sheep walks longest before the edge, the pedestal or another
  // sheep's predicted path (each would make it due for saving again, or
  // bounce one of the two out). Ties: nearest the centre's direction.
  constexpr int kFan = 8;  // each side
  double best = to_centre;
  double best_free_s = -1.0;
  for (int k = 0; k <= 2 * kFan; ++k) {
    // 0, +1, -1, +2, -2, ...: equal scores keep the one nearer the centre.
    const int step = (k + 1) / 2 * (k % 2 == 1 ? 1 : -1);
    const double heading = to_centre + config_.redirect_max_rad * step / kFan;
    const double free_s = walk_free_s(x_mm, y_mm, heading, speed, sheep, target_id);
    if (free_s > best_free_s + 1e-9) {
      best_free_s = free_s;
      best = heading;
    }
  }
  return best;
}

double FieldRules::walk_free_s(double x_mm, double y_mm, double heading_rad, double speed_mm_s,
                               const std::vector<Sheep>& sheep, int target_id) const {
  const double ux = std::cos(heading_rad), uy = std::sin(heading_rad);
  const double vx = speed_mm_s * ux, vy = speed_mm_s * uy;
  double free_s = straight_time_to_edge_s(Sheep{-1, x_mm, y_mm, vx, vy, SheepState::kVisible});
  // The pedestal: the path's centre line within redirect_clearance_mm of the
  // column's axis, from where it first comes that close.
  const double bx = config_.workcell.base_x_mm - x_mm;
  const double by = config_.workcell.base_y_mm - y_mm;
  const double along = bx * ux + by * uy;
  const double miss = std::abs(ux * by - uy * bx);
  const double c = config_.redirect_clearance_mm;
  if (along > 0.0 && miss < c) {
    free_s = std::min(free_s, std::max(0.0, along - std::sqrt(c * c - miss * miss)) / speed_mm_s);
  }
  // Other sheep: straight lines, contact when the centres come within a
  // body's length and width (half of each, for both).
  const double contact_mm = config_.sheep_half_length_mm + config_.sheep_half_width_mm;
  for (const Sheep& s : sheep) {
    if (s.id == target_id || s.state == SheepState::kDead || !finite_sheep(s)) continue;
    const double dx = s.x_mm - x_mm, dy = s.y_mm - y_mm;
    const double rvx = s.vx_mm_s - vx, rvy = s.vy_mm_s - vy;
    const double a = rvx * rvx + rvy * rvy;
    const double b = dx * rvx + dy * rvy;
    const double c0 = dx * dx + dy * dy - contact_mm * contact_mm;
    if (c0 <= 0.0) continue;  // touching now (next to it at the save): not this path's doing
    const double disc = b * b - a * c0;
    if (a < 1e-12 || b >= 0.0 || disc < 0.0) continue;  // never closes to contact
    free_s = std::min(free_s, (-b - std::sqrt(disc)) / a);
  }
  return free_s;
}

double FieldRules::straight_time_to_edge_s(const Sheep& s) const {
  const auto axis = [](double p, double v, double hi) {
    if (v > 0.0) return (hi - p) / v;
    if (v < 0.0) return -p / v;
    return std::numeric_limits<double>::infinity();
  };
  return std::min(axis(s.x_mm, s.vx_mm_s, config_.workcell.field_length_mm),
                  axis(s.y_mm, s.vy_mm_s, config_.workcell.field_width_mm));
}

bool FieldRules::usable_point(double x_mm, double y_mm) const {
  const double m = config_.field_margin_mm;
  if (!(x_mm >= m && x_mm <= config_.workcell.field_length_mm - m && y_mm >= m &&
        y_mm <= config_.workcell.field_width_mm - m)) {
    return false;
  }
  return std::hypot(x_mm - config_.workcell.base_x_mm, y_mm - config_.workcell.base_y_mm) >=
         config_.tool_keepout_mm;
}

bool FieldRules::intercept_in_field(const Intercept& ic, const Sheep& target) const {
  if (!usable_point(ic.x_mm, ic.y_mm)) return false;
  const double m = config_.field_margin_mm;
  const bool centre_inside =
      ic.sheep_x_mm >= m && ic.sheep_x_mm <= config_.workcell.field_length_mm - m &&
      ic.sheep_y_mm >= m && ic.sheep_y_mm <= config_.workcell.field_width_mm - m;
  return centre_inside && ic.t_s <= time_to_boundary(target);
}

int FieldRules::other_sheep_near(const std::vector<Sheep>& sheep, int target_id, double x_mm,
                                 double y_mm, double t_from_s, double t_to_s) const {
  const double r = config_.clearance_mm;
  t_from_s = std::max(0.0, t_from_s);
  for (const Sheep& s : sheep) {
    if (s.id == target_id || s.state == SheepState::kDead || !finite_sheep(s)) continue;
    // Closest approach of the straight-line prediction within the window.
    const double dx = s.x_mm - x_mm;
    const double dy = s.y_mm - y_mm;
    const double v2 = s.vx_mm_s * s.vx_mm_s + s.vy_mm_s * s.vy_mm_s;
    double t = t_from_s;
    if (v2 > 1e-12) t = std::clamp(-(dx * s.vx_mm_s + dy * s.vy_mm_s) / v2, t_from_s, t_to_s);
    if (std::hypot(dx + s.vx_mm_s * t, dy + s.vy_mm_s * t) < r) return s.id;
  }
  return -1;
}

}  // namespace ephor::planner
