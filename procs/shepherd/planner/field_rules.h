#pragma once
// FieldRules: the planners' judgements about sheep and points on the field
// (paper 003, section 3.4, step 1 and the rejections of step 2): when a
// sheep leaves, whether it is already headed toward the centre, whether an
// intercept is usable. All in F (mm, mm/s, s).

#include <vector>

#include "procs/shepherd/planner/bounce_predictor.h"
#include "procs/shepherd/planner/herd_types.h"
#include "procs/shepherd/planner/intercept_solver.h"

namespace ephor::planner {

class FieldRules {
 public:
  explicit FieldRules(const PlannerConfig& config)
      : config_(config),
        bounces_(BouncePredictorConfig{.workcell = config.workcell,
                                       .sheep_half_length_mm = config.sheep_half_length_mm,
                                       .sheep_half_width_mm = config.sheep_half_width_mm,
                                       .horizon_s = config.bounce_horizon_s,
                                       .min_speed_mm_s = config.min_sheep_speed_mm_s}) {}

  const PlannerConfig& config() const { return config_; }
  double centre_x_mm() const { return config_.workcell.centre_x_mm(); }
  double centre_y_mm() const { return config_.workcell.centre_y_mm(); }

  // Seconds until the sheep's centre crosses the field edge moving in a
  // straight line; +inf for a (near) stationary sheep, 0 if already outside.
  double time_to_boundary(const Sheep& sheep) const;
  // Velocity within heading_to_centre_rad of the direction to the centre.
  bool heading_to_centre(const Sheep& sheep) const;
  // Alive, moving, not headed toward the centre (nor in the centre zone)
  // and leaving within the save horizon: paper step 1's conditions.
  bool needs_saving(const Sheep& sheep) const;
  // The same with the time it leaves in given (e.g. a bounced path's).
  bool needs_saving(const Sheep& sheep, double leaves_in_s) const;
  // Indices into `sheep` of those that need saving, soonest to leave first
  // (with config.predict_bounces, leaving along their bounced paths).
  std::vector<int> candidates_by_urgency(const std::vector<Sheep>& sheep) const;

  // The orientation, rad in F, for a tool lowered at (x, y) to send sheep
  // `target_id` on (the touched sheep goes the way the tool faces): within
  // redirect_max_rad of the centre's direction, the heading along which it
  // walks longest before the field edge, the pedestal (its centre line within
  // redirect_clearance_mm of the column) or another sheep's straight path.
  // redirect_clearance_mm = 0: straight at the centre (the paper's rule).
  double redirect_heading(double x_mm, double y_mm, const std::vector<Sheep>& sheep,
                          int target_id) const;
  // Seconds a sheep at (x, y) walking at speed_mm_s along heading_rad goes
  // before one of those; straight lines for everyone.
  double walk_free_s(double x_mm, double y_mm, double heading_rad, double speed_mm_s,
                     const std::vector<Sheep>& sheep, int target_id) const;

  // Inside the field by field_margin_mm and outside the pedestal keep-out.
  bool usable_point(double x_mm, double y_mm) const;
  // Paper step 2's first rejection: tool point or sheep centre outside the
  // field (or on the pedestal), or the sheep gone before the intercept.
  bool intercept_in_field(const Intercept& intercept, const Sheep& target) const;
  // Paper step 2's second rejection (and step 3's re-check): another live
  // sheep's predicted centre comes within clearance_mm of (x, y) between
  // t_from_s and t_to_s from now. Returns that sheep's id, or -1.
  int other_sheep_near(const std::vector<Sheep>& sheep, int target_id, double x_mm, double y_mm,
                       double t_from_s, double t_to_s) const;

 private:
  // Straight-line time to the edge for the sheep's velocity as given (no
  // stationary threshold); +inf for zero velocity.
  double straight_time_to_edge_s(const Sheep& sheep) const;

  PlannerConfig config_;
  BouncePredictor bounces_;
};

// True for a sheep with every field finite.
bool finite_sheep(const Sheep& sheep);

}  // namespace ephor::planner
