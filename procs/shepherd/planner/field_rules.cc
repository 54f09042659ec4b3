#include "procs/shepherd/planner/field_rules.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ephor::planner {

bool finite_sheep(const Sheep& s) {
  return std::isfinite(s.x_mm) && std::isfinite(s.y_mm) && std::isfinite(s.vx_mm_s) &&
         std::isfinite(s.vy_mm_s);
}

double FieldRules::time_to_boundary(const Sheep& s) const {
  const double inf = std::numeric_limits<double>::infinity();
  if (!config_.workcell.inside_field(s.x_mm, s.y_mm)) return 0.0;
  if (std::hypot(s.vx_mm_s, s.vy_mm_s) < config_.min_sheep_speed_mm_s) return inf;
  const auto axis = [inf](double p, double v, double hi) {
    if (v > 0.0) return (hi - p) / v;
    if (v < 0.0) return -p / v;
    return inf;
  };
  return std::min(axis(s.x_mm, s.vx_mm_s, config_.workcell.field_length_mm),
                  axis(s.y_mm, s.vy_mm_s, config_.workcell.field_width_mm));
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
