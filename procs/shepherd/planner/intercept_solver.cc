#include "procs/shepherd/planner/intercept_solver.h"

#include <cmath>

namespace ephor::planner {

std::optional<double> InterceptSolver::earliest_time(double ax, double ay, double px, double py,
                                                     double vx, double vy, double speed_mm_s,
                                                     double delay_s) {
  for (double value : {ax, ay, px, py, vx, vy, speed_mm_s, delay_s}) {
    if (!std::isfinite(value)) return std::nullopt;
  }
  if (speed_mm_s <= 0.0 || delay_s < 0.0) return std::nullopt;
  const double dx = px - ax;
  const double dy = py - ay;
  const double s2 = speed_mm_s * speed_mm_s;
  // g(t) = |d + v t|^2 - s^2 (t - delay)^2; the tool is in time when g(t) <= 0, t >= delay.
  const double a = vx * vx + vy * vy - s2;
  const double b = 2.0 * (dx * vx + dy * vy + s2 * delay_s);
  const double c = dx * dx + dy * dy - s2 * delay_s * delay_s;
  const auto g = [&](double t) { return (a * t + b) * t + c; };
  // Already there when the delay ends (e.g. the sheep walks under the tool).
  const double tol = 1e-9 * (1.0 + dx * dx + dy * dy);
  if (g(delay_s) <= tol) return delay_s;
  // Relative scale for "a == 0" (sheep exactly as fast as the arm).
  if (std::abs(a) <= 1e-12 * s2) {
    if (b >= 0.0) return std::nullopt;
    return -c / b;
  }
  const double disc = b * b - 4.0 * a * c;
  if (disc < 0.0) return std::nullopt;  // only possible when the sheep is faster (a > 0)
  const double sq = std::sqrt(disc);
  // Numerically stable roots.
  const double q = -0.5 * (b + std::copysign(sq, b));
  double r1 = q / a;
  double r2 = (q != 0.0) ? c / q : r1;
  if (r1 > r2) std::swap(r1, r2);
  if (a < 0.0) {
    // Arm faster: g is a downward parabola positive at delay, so delay lies
    // between the roots and the tool is in time from the larger one on.
    return r2 >= delay_s ? std::optional<double>(r2) : std::nullopt;
  }
  // Sheep faster: in time only between the roots, and delay is outside them.
  if (r1 >= delay_s) return r1;
  return std::nullopt;
}

std::optional<Intercept> InterceptSolver::solve(const ArmModel& arm, const Sheep& sheep,
                                                double lead_mm, double delay_s, double centre_x_mm,
                                                double centre_y_mm) {
  const double speed = std::hypot(sheep.vx_mm_s, sheep.vy_mm_s);
  double lead_x = 0.0;
  double lead_y = 0.0;
  if (speed > 1e-6) {
    lead_x = lead_mm * sheep.vx_mm_s / speed;
    lead_y = lead_mm * sheep.vy_mm_s / speed;
  }
  const auto t = earliest_time(arm.x_mm, arm.y_mm, sheep.x_mm + lead_x, sheep.y_mm + lead_y,
                               sheep.vx_mm_s, sheep.vy_mm_s, arm.speed_mm_s, delay_s);
  if (!t) return std::nullopt;
  Intercept out;
  out.t_s = *t;
  out.sheep_x_mm = sheep.x_mm + sheep.vx_mm_s * *t;
  out.sheep_y_mm = sheep.y_mm + sheep.vy_mm_s * *t;
  out.x_mm = out.sheep_x_mm + lead_x;
  out.y_mm = out.sheep_y_mm + lead_y;
  out.theta_rad = std::atan2(centre_y_mm - out.y_mm, centre_x_mm - out.x_mm);
  return out;
}

}  // namespace ephor::planner
