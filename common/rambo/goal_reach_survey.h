#pragma once
// Where a target's diodes can be tagged from at all: for a known motion of
// the target (ground truth, not a prediction), the times at which each
// diode's goal pose (the laser's tip on the goal point, the beam along the
// lens's axis) has an inverse kinematics solution for the PUMA 560 at the
// time and again a hold later. That is the planner's own test before it
// orders a diode (TaggingPlanner::step: reachable at landing and at the end
// of the hold), so a diode the survey finds out of reach for a whole run
// cannot be tagged by any order or timing. Used by ephor-bench-rambo's
// "reach" section to choose where the model file mounts the diodes
// (deploy/rambo/target.pbtxt) and the target's motion envelope.
//
// Times in s from the motion's t = 0; poses in the PUMA's base frame, mm.
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "common/rambo/rambo_cell.h"

namespace ephor::rambo {

struct DiodeReach {
  std::string name;
  int samples = 0;                // times looked at
  int reachable = 0;              // of them, with the goal reachable at t and t + hold
  double first_reachable_s = -1;  // -1 = never
  double longest_window_s = 0.0;  // longest unbroken run of reachable samples, s
  // In reach from t = 0 until this time, s: the first sample out of reach
  // (0 = out of reach at the start; past the span when never out).
  double in_reach_from_start_s = 0.0;
  double reachable_fraction() const {
    return samples > 0 ? static_cast<double>(reachable) / static_cast<double>(samples) : 0.0;
  }
};

struct GoalReachSurveyOptions {
  double duration_s = 120.0;  // span looked at, from t = 0
  double step_s = 0.5;        // between samples
  double hold_s = 2.0;        // the goal must be reachable again this much later (the hold)
};

// target_at(t): the target frame in the PUMA's base at t, mm. Throws
// std::invalid_argument for a step or duration that is not > 0 or a hold < 0.
std::vector<DiodeReach> survey_goal_reach(const RamboCell& cell,
                                          const std::function<Eigen::Isometry3d(double)>& target_at,
                                          const GoalReachSurveyOptions& options = {});

}  // namespace ephor::rambo
