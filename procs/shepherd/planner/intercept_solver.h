#pragma once
// InterceptSolver: where and when the arm can meet a sheep moving in a
// straight line (paper 003, section 3.4, step 2: "an intercept is calculated
// according to arm position and velocity, sheep position and velocity, and
// a delay long enough to allow the arm to move from the elevation plane into
// the object plane").
//
// Model: the tool travels in a straight line in the elevation plane at speed
// s (mm/s), then needs `delay_s` more (lowering, goal overheads) before it
// is in the object plane. The point to meet moves as p + v t. The earliest
// t >= delay with |p + v t - a| <= s (t - delay) is a root of
//   (|v|^2 - s^2) t^2 + 2 (d.v + s^2 delay) t + |d|^2 - s^2 delay^2 = 0,
// d = p - a, solved in closed form. All in F: mm, mm/s, s.

#include <optional>

#include "procs/shepherd/planner/herd_types.h"

namespace ephor::planner {

struct Intercept {
  double t_s = 0.0;   // from now until the tool is down at (x, y) and the sheep's nose is there
  double x_mm = 0.0;  // tool point in F
  double y_mm = 0.0;
  double sheep_x_mm = 0.0;  // the sheep's centre at t_s, F
  double sheep_y_mm = 0.0;
  double theta_rad = 0.0;  // tool orientation: facing the field centre from (x, y)
};

class InterceptSolver {
 public:
  // Earliest t >= delay_s at which a point starting at (px, py) with
  // velocity (vx, vy) can be met by a tool starting at (ax, ay) that moves at
  // speed_mm_s and then waits delay_s. nullopt when the point is too fast to
  // catch (or speed_mm_s <= 0, or any input is not finite).
  static std::optional<double> earliest_time(double ax, double ay, double px, double py, double vx,
                                             double vy, double speed_mm_s, double delay_s);

  // Intercept of `sheep` by `arm`: the tool point lies `lead_mm` ahead of
  // the sheep's centre along its heading (so the lowered tool meets the
  // nose), delay_s covers lowering and overheads. centre_x/y: the field
  // centre the tool should face. nullopt when no intercept exists.
  static std::optional<Intercept> solve(const ArmModel& arm, const Sheep& sheep, double lead_mm,
                                        double delay_s, double centre_x_mm, double centre_y_mm);
};

}  // namespace ephor::planner
