#include "procs/shepherd/planner/planner.h"

#include <stdexcept>

#include "procs/shepherd/planner/lookahead_planner.h"
#include "procs/shepherd/planner/multi_sheep_planner.h"
#include "procs/shepherd/planner/single_sheep_planner.h"

namespace ephor::planner {

std::vector<std::string> planner_kinds() { return {"single", "multi", "lookahead"}; }

std::unique_ptr<Planner> make_planner(const std::string& kind, const PlannerConfig& config) {
  if (kind == "single") return std::make_unique<SingleSheepPlanner>(config);
  if (kind == "multi") return std::make_unique<MultiSheepPlanner>(config);
  if (kind == "lookahead") return std::make_unique<LookaheadPlanner>(config);
  throw std::invalid_argument("unknown planner kind '" + kind +
                              "' (want single, multi or lookahead)");
}

}  // namespace ephor::planner
