#include "common/rambo/goal_reach_survey.h"

#include <cmath>
#include <stdexcept>

#include "common/arm/puma560.h"

namespace ephor::rambo {

std::vector<DiodeReach> survey_goal_reach(const RamboCell& cell,
                                          const std::function<Eigen::Isometry3d(double)>& target_at,
                                          const GoalReachSurveyOptions& o) {
  if (!(o.step_s > 0.0) || !(o.duration_s > 0.0) || !(o.hold_s >= 0.0))
    throw std::invalid_argument("survey_goal_reach: step and duration must be > 0, hold >= 0");
  const arm::Puma560 arm(cell.tool_length_mm);
  const int n = static_cast<int>(std::floor(o.duration_s / o.step_s)) + 1;
  // The pose at every sample and every sample + hold: target_at may be a
  // body integrated forward, cheapest queried in increasing time.
  std::vector<Eigen::Isometry3d> at(static_cast<std::size_t>(n)),
      later(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) at[static_cast<std::size_t>(k)] = target_at(o.step_s * k);
  for (int k = 0; k < n; ++k)
    later[static_cast<std::size_t>(k)] = target_at(o.step_s * k + o.hold_s);
  std::vector<DiodeReach> out;
  for (std::size_t i = 0; i < cell.diodes.size(); ++i) {
    DiodeReach r;
    r.name = cell.diodes[i].name;
    const Eigen::Isometry3d goal = cell.goal_in_target(static_cast<int>(i));
    int run = 0;
    bool from_start = true;
    for (int k = 0; k < n; ++k) {
      ++r.samples;
      const auto& p = at[static_cast<std::size_t>(k)];
      const auto& q = later[static_cast<std::size_t>(k)];
      const bool ok = !arm.inverse(p * goal).empty() && !arm.inverse(q * goal).empty();
      if (!ok) {
        if (from_start) r.in_reach_from_start_s = o.step_s * k;
        from_start = false;
        run = 0;
        continue;
      }
      ++r.reachable;
      if (r.first_reachable_s < 0.0) r.first_reachable_s = o.step_s * k;
      ++run;
      r.longest_window_s = std::max(r.longest_window_s, o.step_s * (run - 1));
    }
    if (from_start) r.in_reach_from_start_s = o.step_s * n;
    out.push_back(r);
  }
  return out;
}

}  // namespace ephor::rambo
