#include "procs/planner/multi_sheep_planner.h"

namespace ephor::planner {

CandidateVerdict MultiSheepPlanner::judge(const Scene& scene, const Sheep& sheep,
                                          Intercept* intercept) const {
  CandidateVerdict v;
  v.sheep_id = sheep.id;
  v.time_to_boundary_s = rules().time_to_boundary(sheep);
  const auto ic =
      InterceptSolver::solve(scene.arm, sheep, config().sheep_lead_mm, lowering_delay_s(scene.arm),
                             rules().centre_x_mm(), rules().centre_y_mm());
  if (!ic) {
    v.verdict = Verdict::kNoIntercept;
    return v;
  }
  if (intercept != nullptr) *intercept = *ic;
  if (!rules().intercept_in_field(*ic, sheep)) {
    v.verdict = Verdict::kOutsideField;
    return v;
  }
  // The tool is coming down from (t - lowering) and stays down until the
  // touch and the raise.
  const double from = ic->t_s - scene.arm.lowering_time_s - scene.arm.overhead_s;
  const double to = ic->t_s + scene.arm.raise_time_s + scene.arm.overhead_s;
  v.blocking_sheep = rules().other_sheep_near(scene.sheep, sheep.id, ic->x_mm, ic->y_mm, from, to);
  v.verdict = v.blocking_sheep >= 0 ? Verdict::kOnOtherSheepPath : Verdict::kAccepted;
  return v;
}

std::vector<int> MultiSheepPlanner::candidate_order(const Scene&,
                                                    const std::vector<int>& by_urgency) {
  return by_urgency;
}

std::optional<SavePlan> MultiSheepPlanner::choose(const Scene& scene, int* candidates) {
  verdicts_.clear();
  const std::vector<int> by_urgency = rules().candidates_by_urgency(scene.sheep);
  *candidates = static_cast<int>(by_urgency.size());
  for (int index : candidate_order(scene, by_urgency)) {
    const Sheep& sheep = scene.sheep[static_cast<size_t>(index)];
    Intercept ic;
    const CandidateVerdict v = judge(scene, sheep, &ic);
    verdicts_.push_back(v);
    if (v.verdict == Verdict::kAccepted) return SavePlan{sheep.id, ic};
  }
  return std::nullopt;
}

}  // namespace ephor::planner
