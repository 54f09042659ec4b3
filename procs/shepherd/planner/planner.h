#pragma once
// Planner: the shepherd's executive (paper 003, section 3.4). One planning
// job per objects update: it looks at the newest scene and returns at most
// one arm goal to send now. The goal protocol: a planner keeps at most one
// goal outstanding, waits for its motion_done (by goal_id) before the next,
// keeps re-evaluating on every job meanwhile, and treats a goal with no
// motion_done within its timeout as failed. Never blocks.
//
// Threading: not thread-safe; call plan() and on_motion_done() from one
// thread (the main queues motion_done events for the planning task).

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "procs/shepherd/planner/herd_types.h"

namespace ephor::planner {

class Planner {
 public:
  virtual ~Planner() = default;

  // One planning job. Returns the goal to send now, if any. Bad sheep
  // (non-finite values) are ignored and counted in status().bad_sheep.
  virtual std::optional<Goal> plan(const Scene& scene) = 0;
  // How goal `goal_id` ended. Returns false for ids that are not the
  // outstanding goal (late, duplicated or from another planner run).
  virtual bool on_motion_done(int64_t goal_id, bool succeeded) = 0;
  virtual PlannerStatus status() const = 0;
  // "single", "multi" or "lookahead".
  virtual std::string kind() const = 0;
};

// The planner kinds make_planner() knows.
std::vector<std::string> planner_kinds();
// Throws std::invalid_argument naming the known kinds for an unknown one.
std::unique_ptr<Planner> make_planner(const std::string& kind, const PlannerConfig& config);

}  // namespace ephor::planner
