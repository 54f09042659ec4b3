#include "procs/shepherd/planner/lookahead_planner.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <utility>

namespace ephor::planner {

namespace {

constexpr double kSlackEps = 1e-6;

// The world as the search sees it part-way through an ordering.
struct SimState {
  double t_s = 0.0;  // time from now
  double arm_x_mm = 0.0;
  double arm_y_mm = 0.0;
  int escapes = 0;
  double lateness_s = 0.0;
  double min_slack_s = std::numeric_limits<double>::infinity();
};

}  // namespace

LookaheadPlanner::LookaheadPlanner(const PlannerConfig& config, MonoClock clock)
    : MultiSheepPlanner(config), clock_(std::move(clock)) {
  if (!clock_) {
    clock_ = [] {
      return static_cast<int64_t>(std::chrono::duration_cast<std::chrono::nanoseconds>(
                                      std::chrono::steady_clock::now().time_since_epoch())
                                      .count());
    };
  }
}

bool OrderingScore::better_than(const OrderingScore& o) const {
  if (escapes != o.escapes) return escapes < o.escapes;
  if (std::abs(lateness_s - o.lateness_s) > kSlackEps) return lateness_s < o.lateness_s;
  if (std::abs(min_slack_s - o.min_slack_s) > kSlackEps) return min_slack_s > o.min_slack_s;
  return finish_s < o.finish_s - kSlackEps;
}

OrderingScore LookaheadPlanner::score(const Scene& scene, const std::vector<int>& by_urgency,
                                      const std::vector<int>& ordering) const {
  const ArmModel& arm0 = scene.arm;
  SimState st;
  st.arm_x_mm = arm0.x_mm;
  st.arm_y_mm = arm0.y_mm;
  // The ordering, then every other candidate most urgent first (a greedy
  // completion), so that orderings are compared over the same sheep.
  std::vector<int> sequence = ordering;
  for (int index : by_urgency) {
    if (std::find(ordering.begin(), ordering.end(), index) == ordering.end()) {
      sequence.push_back(index);
    }
  }
  for (int index : sequence) {
    const Sheep& s0 = scene.sheep[static_cast<size_t>(index)];
    // The sheep where it will be when the arm is free for it.
    Sheep s = s0;
    s.x_mm += s0.vx_mm_s * st.t_s;
    s.y_mm += s0.vy_mm_s * st.t_s;
    const double ttb = rules().time_to_boundary(s0);
    ArmModel arm = arm0;
    arm.x_mm = st.arm_x_mm;
    arm.y_mm = st.arm_y_mm;
    bool hopeful = false;
    const auto ic = intercept_for(arm, s, nullptr, &hopeful);
    if (!ic || hopeful || !rules().intercept_in_field(*ic, s)) {
      // Cannot be saved this late: the arm does not go. How late it is (the
      // arm reaching the point where the sheep leaves) tells near misses,
      // which a conservative arm model may still save, from hopeless ones.
      ++st.escapes;
      const double exit_x = s0.x_mm + s0.vx_mm_s * ttb;
      const double exit_y = s0.y_mm + s0.vy_mm_s * ttb;
      const double reach =
          st.t_s + std::hypot(exit_x - st.arm_x_mm, exit_y - st.arm_y_mm) / arm0.speed_mm_s +
          lowering_delay_s(arm0);
      st.lateness_s += std::max(0.0, reach - ttb);
      continue;
    }
    const double t_meet = st.t_s + ic->t_s;
    st.min_slack_s = std::min(st.min_slack_s, ttb - t_meet);
    // Down until the touch (already touching: the tool is placed on the
    // body), then up again before the next.
    st.t_s = t_meet + arm0.raise_time_s + arm0.overhead_s;
    st.arm_x_mm = ic->x_mm;
    st.arm_y_mm = ic->y_mm;
  }
  OrderingScore out;
  out.escapes = st.escapes;
  out.lateness_s = st.lateness_s;
  out.min_slack_s = std::isfinite(st.min_slack_s) ? st.min_slack_s : 1e9;
  out.finish_s = st.t_s;
  return out;
}

std::vector<int> LookaheadPlanner::search(const Scene& scene, const std::vector<int>& by_urgency) {
  const int64_t start_ns = clock_();
  const auto budget_ns = static_cast<int64_t>(config().lookahead_budget_s * 1e9);
  stats_ = LookaheadStats{};
  const size_t pool_size = std::min(
      by_urgency.size(), static_cast<size_t>(std::max(1, config().lookahead_max_candidates)));
  const std::vector<int> pool(by_urgency.begin(),
                              by_urgency.begin() + static_cast<long>(pool_size));
  const size_t depth =
      std::min(pool.size(), static_cast<size_t>(std::max(1, config().lookahead_depth)));

  std::vector<int> best;
  std::vector<int> current;
  std::vector<bool> used(pool.size(), false);
  bool out_of_time = false;
  // Depth-first over ordered selections; pool is most-urgent-first, so the
  // first leaf is the greedy ordering.
  const auto dfs = [&](auto&& self) -> void {
    if (out_of_time) return;
    if (current.size() == depth) {
      const OrderingScore sc = score(scene, by_urgency, current);
      if (stats_.orderings_scored == 0) stats_.greedy_score = sc;
      if (stats_.orderings_scored == 0 || sc.better_than(stats_.best_score)) {
        stats_.best_score = sc;
        best = current;
      }
      ++stats_.orderings_scored;
      if (clock_() - start_ns >= budget_ns) out_of_time = true;
      return;
    }
    for (size_t i = 0; i < pool.size() && !out_of_time; ++i) {
      if (used[i]) continue;
      used[i] = true;
      current.push_back(pool[i]);
      self(self);
      current.pop_back();
      used[i] = false;
    }
  };
  if (depth > 0) dfs(dfs);
  stats_.exhausted = !out_of_time;
  stats_.elapsed_s = static_cast<double>(clock_() - start_ns) * 1e-9;

  std::vector<int> order = best;
  for (int index : by_urgency) {
    if (std::find(order.begin(), order.end(), index) == order.end()) order.push_back(index);
  }
  for (int index : best) stats_.best.push_back(scene.sheep[static_cast<size_t>(index)].id);
  return order;
}

std::vector<int> LookaheadPlanner::candidate_order(const Scene& scene,
                                                   const std::vector<int>& by_urgency) {
  return search(scene, by_urgency);
}

}  // namespace ephor::planner
