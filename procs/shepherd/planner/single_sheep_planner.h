#pragma once
// SingleSheepPlanner: paper 003, section 3.4, the single-sheep planner.
// "When the sheep is spotted, an intercept point is found on the field
// boundary, the robot positions itself at the intercept point in the
// elevation plane with the manipulator oriented to catch it, and then the
// manipulator is lowered to the object plane. Until the sheep reaches the
// intercept point, the position and orientation of the manipulator are
// corrected ... When the sheep reaches the manipulator, it is reoriented
// toward the center of the field. Finally, the manipulator is ... placed in
// the lower right corner."
//
// The intercept is where the sheep's path meets the field edge (pulled in by
// the field margin); when the arm cannot get there before the sheep, the
// earliest intercept is used instead. With several sheep it minds the one
// leaving soonest and ignores the others (no path checks).

#include "procs/shepherd/planner/save_cycle_planner.h"

namespace ephor::planner {

class SingleSheepPlanner : public SaveCyclePlanner {
 public:
  explicit SingleSheepPlanner(const PlannerConfig& config) : SaveCyclePlanner(config) {}
  std::string kind() const override { return "single"; }

  // Where the sheep's path leaves the field (less the margin), with the
  // tool placed there; nullopt when the arm cannot be down there before the
  // sheep's nose arrives. `delay_s` as in InterceptSolver.
  std::optional<Intercept> boundary_intercept(const ArmModel& arm, const Sheep& sheep,
                                              double delay_s) const;

 protected:
  std::optional<SavePlan> choose(const Scene& scene, int* candidates) override;
  std::optional<Intercept> replan_at_intercept(const Scene& scene, const Sheep& target) override;
  bool checks_other_sheep() const override { return false; }
  bool parks_after_save() const override { return true; }

 private:
  std::optional<Intercept> best_intercept(const ArmModel& arm, const Sheep& sheep,
                                          double delay_s) const;
};

}  // namespace ephor::planner
