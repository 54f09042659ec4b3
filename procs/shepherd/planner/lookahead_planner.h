#pragma once
// LookaheadPlanner: the "exploring all possibilities of the next n sheep to
// save" end of paper 003's spectrum (section 3.4), made anytime. It searches
// orderings of the next n saves (depth-first, the greedy most-urgent-first
// ordering first) within a time budget measured on the monotonic clock,
// scores each by simulating arm travel and straight-line sheep motion, and
// returns its best ordering so far when the budget ends. The save cycle
// (move, verify, lower, raise) is the multi-sheep planner's; only the order
// in which candidates are tried differs.
//
// Score of an ordering (followed by the remaining candidates most urgent
// first), compared in this order: fewer predicted escapes (a sheep that
// cannot be intercepted on the field by the time the arm is free for it),
// then less total lateness for those, then larger minimum slack (time to boundary minus intercept
// time), then earlier finish.

#include <cstdint>
#include <functional>
#include <vector>

#include "procs/shepherd/planner/multi_sheep_planner.h"

namespace ephor::planner {

struct OrderingScore {
  int escapes = 0;
  double lateness_s = 0.0;  // summed over predicted escapes: how late the arm would be
  double min_slack_s = 0.0;
  double finish_s = 0.0;
  // True when this is strictly better than `other`.
  bool better_than(const OrderingScore& other) const;
};

struct LookaheadStats {
  int64_t orderings_scored = 0;
  bool exhausted = false;  // every ordering was scored before the budget ended
  double elapsed_s = 0.0;  // wall time of the search (monotonic clock)
  std::vector<int> best;   // sheep ids, best ordering found
  OrderingScore best_score;
  OrderingScore greedy_score;  // the most-urgent-first ordering's score
};

class LookaheadPlanner : public MultiSheepPlanner {
 public:
  // Monotonic clock in ns for the budget; tests may pass a fake one.
  using MonoClock = std::function<int64_t()>;
  explicit LookaheadPlanner(const PlannerConfig& config, MonoClock clock = nullptr);
  std::string kind() const override { return "lookahead"; }

  // Searches orderings of the sheep needing saving in `scene`; returns the
  // best ordering (indices into scene.sheep, most preferred first, then the
  // others by urgency). Fills last_stats().
  std::vector<int> search(const Scene& scene, const std::vector<int>& by_urgency);
  // Scores one ordering (indices into scene.sheep) by simulation.
  OrderingScore score(const Scene& scene, const std::vector<int>& by_urgency,
                      const std::vector<int>& ordering) const;
  const LookaheadStats& last_stats() const { return stats_; }

 protected:
  std::vector<int> candidate_order(const Scene& scene, const std::vector<int>& by_urgency) override;

 private:
  MonoClock clock_;
  LookaheadStats stats_;
};

}  // namespace ephor::planner
