#include "procs/shepherd/planner/single_sheep_planner.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ephor::planner {

std::optional<Intercept> SingleSheepPlanner::boundary_intercept(const ArmModel& arm,
                                                                const Sheep& sheep,
                                                                double delay_s) const {
  const double speed = std::hypot(sheep.vx_mm_s, sheep.vy_mm_s);
  if (speed < config().min_sheep_speed_mm_s) return std::nullopt;
  const double m = config().field_margin_mm;
  const double lx = config().workcell.field_length_mm - m;
  const double ly = config().workcell.field_width_mm - m;
  // Time at which the sheep's centre reaches the shrunken field edge.
  const double inf = std::numeric_limits<double>::infinity();
  const auto axis = [inf](double p, double v, double lo, double hi) {
    if (v > 0.0) return (hi - p) / v;
    if (v < 0.0) return (lo - p) / v;
    return inf;
  };
  const double t_edge =
      std::min(axis(sheep.x_mm, sheep.vx_mm_s, m, lx), axis(sheep.y_mm, sheep.vy_mm_s, m, ly));
  if (!(t_edge > 0.0) || !std::isfinite(t_edge)) return std::nullopt;
  Intercept ic;
  ic.x_mm = sheep.x_mm + sheep.vx_mm_s * t_edge;
  ic.y_mm = sheep.y_mm + sheep.vy_mm_s * t_edge;
  // The nose (half a body ahead of the centre) arrives first.
  ic.t_s = t_edge - config().sheep_half_length_mm / speed;
  ic.sheep_x_mm = sheep.x_mm + sheep.vx_mm_s * ic.t_s;
  ic.sheep_y_mm = sheep.y_mm + sheep.vy_mm_s * ic.t_s;
  ic.theta_rad = std::atan2(rules().centre_y_mm() - ic.y_mm, rules().centre_x_mm() - ic.x_mm);
  const double need = std::hypot(ic.x_mm - arm.x_mm, ic.y_mm - arm.y_mm) / arm.speed_mm_s + delay_s;
  if (need > ic.t_s || !rules().usable_point(ic.x_mm, ic.y_mm)) return std::nullopt;
  return ic;
}

std::optional<Intercept> SingleSheepPlanner::best_intercept(const ArmModel& arm, const Sheep& sheep,
                                                            double delay_s) const {
  if (auto ic = boundary_intercept(arm, sheep, delay_s)) return ic;
  auto ic = InterceptSolver::solve(arm, sheep, config().sheep_lead_mm, delay_s,
                                   rules().centre_x_mm(), rules().centre_y_mm());
  if (ic && rules().intercept_in_field(*ic, sheep)) return ic;
  return std::nullopt;
}

std::optional<SavePlan> SingleSheepPlanner::choose(const Scene& scene, int* candidates) {
  const std::vector<int> by_urgency = save_candidates(scene);
  *candidates = static_cast<int>(by_urgency.size());
  if (by_urgency.empty()) return std::nullopt;
  const Sheep& sheep = scene.sheep[static_cast<size_t>(by_urgency.front())];
  const auto ic = best_intercept(scene.arm, sheep, lowering_delay_s(scene.arm));
  if (!ic) return std::nullopt;
  return SavePlan{sheep.id, *ic};
}

std::optional<Intercept> SingleSheepPlanner::replan_at_intercept(const Scene& scene,
                                                                 const Sheep& target) {
  return best_intercept(scene.arm, target, scene.arm.lowering_time_s + scene.arm.overhead_s);
}

}  // namespace ephor::planner
