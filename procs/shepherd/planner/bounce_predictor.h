#pragma once
// BouncePredictor: when each sheep leaves the field if it keeps driving and
// bounces as the simulated (and the paper's woolled) sheep do: off the PUMA's
// pedestal and off each other, its heading reflected about the contact normal
// (common/shepherd/sim/world.h). The planners' straight-line rule
// (FieldRules::time_to_boundary) misses both: a sheep walking out may be
// turned back in by another, and one walking in is sent out again.
//
// All sheep are stepped together (a bounce needs both bodies) for at most
// horizon_s; a sheep still on the field then is given its straight-line time
// from where it is. Bodies are rectangles along the velocity, contact judged
// along the line between the centres (as KinematicField's). In F: mm, mm/s, s.

#include <vector>

#include "procs/shepherd/planner/herd_types.h"

namespace ephor::planner {

struct BouncePredictorConfig {
  geometry::Workcell workcell;  // field and pedestal
  double sheep_half_length_mm = 114.5;
  double sheep_half_width_mm = 44.5;
  bool pedestal = true;
  bool sheep = true;        // bounces between sheep
  double horizon_s = 20.0;  // stepped this far ahead
  double step_s = 0.1;
  double min_speed_mm_s = 3.0;  // slower sheep stand still
};

class BouncePredictor {
 public:
  explicit BouncePredictor(const BouncePredictorConfig& config) : config_(config) {}

  // Seconds until each sheep's centre leaves the field (same order as
  // `sheep`): 0 if outside now, +inf for a dead or standing sheep or one that
  // never leaves. Non-finite sheep are +inf and take no part in bounces.
  std::vector<double> exit_times_s(const std::vector<Sheep>& sheep) const;

 private:
  BouncePredictorConfig config_;
};

}  // namespace ephor::planner
