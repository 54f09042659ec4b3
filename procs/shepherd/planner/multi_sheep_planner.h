#pragma once
// MultiSheepPlanner: paper 003, section 3.4, the multi-sheep planner.
//   1. Choose the sheep that will leave the field soonest and is not already
//      headed toward the centre; if none, park at the lower-right corner.
//   2. Intercept it from the arm's position and speed, the sheep's position
//      and velocity and the lowering delay; if the intercept is outside the
//      field or on another sheep's predicted path, consider the next sheep.
//   3. Move there in the elevation plane, re-check that no sheep is under
//      the arm, lower over the target (touching turns it toward the centre),
//      raise.
//   4. Start over.
// Steps 3 and 4 are the SaveCyclePlanner state machine; this class is steps
// 1 and 2. candidate_order() is the hook the look-ahead planner overrides.

#include <vector>

#include "procs/shepherd/planner/save_cycle_planner.h"

namespace ephor::planner {

// Why a candidate was accepted or passed over in the last choice.
enum class Verdict { kAccepted, kNoIntercept, kOutsideField, kOnOtherSheepPath };

struct CandidateVerdict {
  int sheep_id = -1;
  double time_to_boundary_s = 0.0;
  Verdict verdict = Verdict::kNoIntercept;
  int blocking_sheep = -1;  // for kOnOtherSheepPath
  // The intercept is outside the arm's current configuration's region
  // (its time includes ArmModel::configuration_switch_s).
  bool needs_switch = false;
  // The sheep needs a configuration change that would come too late: the
  // intercept assumes the straight-line time, which the arm cannot make.
  // Saved only when no other sheep can be (see choose()).
  bool hopeful = false;
};

class MultiSheepPlanner : public SaveCyclePlanner {
 public:
  explicit MultiSheepPlanner(const PlannerConfig& config) : SaveCyclePlanner(config) {}
  std::string kind() const override { return "multi"; }

  // The candidates examined by the last choice, in the order examined.
  const std::vector<CandidateVerdict>& last_verdicts() const { return verdicts_; }

  // Step 2's intercept for one sheep (from the elevation plane, with the
  // lowering delay); may lie outside the field. *hopeful (CandidateVerdict::
  // hopeful): a configuration change is needed and the intercept after it
  // is unusable, so this is the straight-line intercept instead.
  std::optional<Intercept> intercept_for(const ArmModel& arm, const Sheep& sheep,
                                         bool* needs_switch = nullptr,
                                         bool* hopeful = nullptr) const;
  // Step 2 for one sheep: the intercept and whether it is usable.
  CandidateVerdict judge(const Scene& scene, const Sheep& sheep, Intercept* intercept) const;

 protected:
  std::optional<SavePlan> choose(const Scene& scene, int* candidates) override;
  // Indices into scene.sheep of the sheep needing saving, most urgent
  // first (`by_urgency`); returns the order in which to try them.
  virtual std::vector<int> candidate_order(const Scene& scene, const std::vector<int>& by_urgency);

 private:
  std::vector<CandidateVerdict> verdicts_;
};

}  // namespace ephor::planner
