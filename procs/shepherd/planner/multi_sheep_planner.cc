#include "procs/shepherd/planner/multi_sheep_planner.h"

#include <optional>

namespace ephor::planner {

std::optional<Intercept> MultiSheepPlanner::intercept_for(const ArmModel& arm, const Sheep& sheep,
                                                          bool* needs_switch, bool* hopeful) const {
  // The tool goes just behind the sheep's nose; when that point is already
  // off the field, onto the sheep's mark instead (still on its body, half a
  // body length of timing slack either way).
  std::optional<Intercept> ic;
  bool switching = false;
  bool too_late = false;
  for (const double lead : {config().sheep_lead_mm, 0.0}) {
    ic = InterceptSolver::solve(arm, sheep, lead, lowering_delay_s(arm), rules().centre_x_mm(),
                                rules().centre_y_mm());
    switching = false;
    too_late = false;
    // The straight-line time is a lie when the arm must change configuration
    // or go around its column to get there: meet the sheep later.
    if (ic) {
      const double extra = switch_time_s(arm, ic->x_mm, ic->y_mm);
      if (extra > 0.0) {
        switching = extra >= arm.configuration_switch_s;
        const auto later = InterceptSolver::solve(arm, sheep, lead, lowering_delay_s(arm) + extra,
                                                  rules().centre_x_mm(), rules().centre_y_mm());
        // Only when the later intercept is still usable: the extra time is an
        // estimate (a switch took 7.6-14 s), and holding while the sheep
        // leaves loses it for sure (the one-sheep integration run did). A
        // switch that comes too late is a last hope (choose()).
        if (later && rules().intercept_in_field(*later, sheep)) {
          ic = later;
        } else {
          too_late = switching;
        }
      }
    }
    if (ic && rules().intercept_in_field(*ic, sheep)) break;
  }
  if (needs_switch != nullptr) *needs_switch = switching;
  if (hopeful != nullptr) *hopeful = too_late;
  return ic;
}

CandidateVerdict MultiSheepPlanner::judge(const Scene& scene, const Sheep& sheep,
                                          Intercept* intercept) const {
  CandidateVerdict v;
  v.sheep_id = sheep.id;
  v.time_to_boundary_s = rules().time_to_boundary(sheep);
  const std::optional<Intercept> ic = intercept_for(scene.arm, sheep, &v.needs_switch, &v.hopeful);
  if (!ic) {
    v.verdict = Verdict::kNoIntercept;
    return v;
  }
  if (intercept != nullptr) *intercept = *ic;
  if (!rules().intercept_in_field(*ic, sheep)) {
    v.verdict = Verdict::kOutsideField;
    return v;
  }
  // "If it intercepts the expected location of a second sheep": while the
  // tool comes down onto the intercept.
  const double from = ic->t_s - scene.arm.lowering_time_s - scene.arm.overhead_s;
  const double to = ic->t_s;
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
  const std::vector<int> by_urgency = save_candidates(scene);
  *candidates = static_cast<int>(by_urgency.size());
  std::optional<SavePlan> last_resort;
  // A sheep that can only be met after a configuration change (12-14 s of
  // arm time) and still has time to spare is deferred: a sheep reachable as
  // the arm is gets saved first; the switch happens when nothing else can be.
  std::optional<SavePlan> deferred;
  // A sheep reachable only by a configuration change that comes too late:
  // the arm tries only when that sheep is alone on the field (it would be
  // lost for sure otherwise; the one-sheep integration run needs this). With
  // others about, the 12-14 s swing costs the sheep that come due meanwhile:
  // on the stand-in (PUMA, 4 sheep, 30 seeds x 10 min) trying it in its
  // turn of urgency gave 18.9 escapes per 10 min, whenever no other sheep
  // was saveable 15.9, only when alone 14.9.
  std::optional<SavePlan> hopeful;
  for (int index : candidate_order(scene, by_urgency)) {
    const Sheep& sheep = scene.sheep[static_cast<size_t>(index)];
    Intercept ic;
    const CandidateVerdict v = judge(scene, sheep, &ic);
    verdicts_.push_back(v);
    if (v.verdict == Verdict::kAccepted) {
      if (v.hopeful) {
        if (!hopeful) hopeful = SavePlan{sheep.id, ic, false};
        continue;
      }
      if (v.needs_switch && v.time_to_boundary_s > ic.t_s + config().switch_defer_slack_s) {
        if (!deferred) deferred = SavePlan{sheep.id, ic, false};
        continue;
      }
      return SavePlan{sheep.id, ic, false};
    }
    if (v.verdict == Verdict::kOnOtherSheepPath && !v.hopeful && !last_resort &&
        config().last_resort_on_other_path) {
      last_resort = SavePlan{sheep.id, ic, true};
    }
  }
  if (deferred) return deferred;
  if (last_resort) return last_resort;
  if (hopeful && scene.sheep.size() == 1) return hopeful;
  return std::nullopt;
}

}  // namespace ephor::planner
