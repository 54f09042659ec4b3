#include "common/rambo/task_orderer.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace ephor::rambo {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();

std::int64_t factorial(int n) {
  std::int64_t f = 1;
  for (int i = 2; i <= n; ++i) f *= i;
  return f;
}
}  // namespace

const char* to_string(OrderingMethod m) {
  switch (m) {
    case OrderingMethod::kGreedy:
      return "greedy";
    case OrderingMethod::kExhaustive:
      return "exhaustive";
    case OrderingMethod::kDynamicProgramming:
      return "dp";
  }
  return "?";
}

TaskOrderer::TaskOrderer(std::vector<double> hold_s, ReachingDurationFn reaching_duration)
    : hold_s_(std::move(hold_s)), reaching_duration_(std::move(reaching_duration)) {
  if (!reaching_duration_)
    throw std::invalid_argument("TaskOrderer: empty reaching-duration callback");
  for (std::size_t i = 0; i < hold_s_.size(); ++i) {
    if (!std::isfinite(hold_s_[i]) || hold_s_[i] < 0.0)
      throw std::invalid_argument("TaskOrderer: task " + std::to_string(i) +
                                  " has a hold time that is not a finite number >= 0 s");
  }
}

double TaskOrderer::reach(int from, int to, double launch_s, std::int64_t* count) const {
  ++*count;
  const double t = reaching_duration_(from, to, launch_s);
  // A negative or NaN duration is the callback's bug; treat as unreachable.
  return (std::isfinite(t) && t >= 0.0) ? t : kInf;
}

TaskOrder TaskOrderer::evaluate(const std::vector<int>& order, double start_s) const {
  TaskOrder r;
  r.order = order;
  double t = start_s, moving = 0.0;
  int from = kInitialTrajectory;
  for (int to : order) {
    if (to < 0 || to >= size())
      throw std::invalid_argument("TaskOrderer::evaluate: bad task index");
    const double d = reach(from, to, t, &r.reaching_trajectories);
    if (!std::isfinite(d)) return r;
    r.launch_s.push_back(t);
    r.arrival_s.push_back(t + d);
    t += d + hold_s_[static_cast<std::size_t>(to)];
    r.done_s.push_back(t);
    moving += d;
    from = to;
  }
  r.feasible = true;
  r.total_time_s = t - start_s;
  r.moving_time_s = moving;
  return r;
}

TaskOrder TaskOrderer::greedy(double start_s) const {
  // Section 10.1: from wherever the tool is, compute the reaching trajectory
  // to every remaining task and take the shortest.
  TaskOrder r;
  std::vector<bool> done(hold_s_.size(), false);
  double t = start_s, moving = 0.0;
  int from = kInitialTrajectory;
  for (int step = 0; step < size(); ++step) {
    int best = -1;
    double best_d = kInf;
    for (int to = 0; to < size(); ++to) {
      if (done[static_cast<std::size_t>(to)]) continue;
      const double d = reach(from, to, t, &r.reaching_trajectories);
      if (d < best_d) best_d = d, best = to;
    }
    if (best < 0) return r;  // nothing reachable: infeasible
    done[static_cast<std::size_t>(best)] = true;
    r.order.push_back(best);
    r.launch_s.push_back(t);
    r.arrival_s.push_back(t + best_d);
    t += best_d + hold_s_[static_cast<std::size_t>(best)];
    r.done_s.push_back(t);
    moving += best_d;
    from = best;
  }
  r.feasible = true;
  r.total_time_s = t - start_s;
  r.moving_time_s = moving;
  return r;
}

TaskOrder TaskOrderer::exhaustive(double start_s) const {
  // Depth-first over the tree of ordered prefixes: each edge is one reaching
  // trajectory, computed once for every prefix that shares it.
  if (size() > kMaxExhaustiveTasks)
    throw std::invalid_argument("TaskOrderer::exhaustive: more than " +
                                std::to_string(kMaxExhaustiveTasks) + " tasks");
  TaskOrder best;
  std::int64_t count = 0;
  const int n = size();
  std::vector<int> prefix;
  std::vector<double> launch, arrival, done_at;
  std::vector<bool> used(static_cast<std::size_t>(n), false);
  std::function<void(int, double, double)> dfs = [&](int from, double t, double moving) {
    if (static_cast<int>(prefix.size()) == n) {
      if (t - start_s < best.total_time_s) {
        best.feasible = true;
        best.order = prefix;
        best.launch_s = launch;
        best.arrival_s = arrival;
        best.done_s = done_at;
        best.total_time_s = t - start_s;
        best.moving_time_s = moving;
      }
      return;
    }
    for (int to = 0; to < n; ++to) {
      if (used[static_cast<std::size_t>(to)]) continue;
      const double d = reach(from, to, t, &count);
      if (!std::isfinite(d)) continue;
      const double t_done = t + d + hold_s_[static_cast<std::size_t>(to)];
      used[static_cast<std::size_t>(to)] = true;
      prefix.push_back(to);
      launch.push_back(t);
      arrival.push_back(t + d);
      done_at.push_back(t_done);
      dfs(to, t_done, moving + d);
      done_at.pop_back();
      arrival.pop_back();
      launch.pop_back();
      prefix.pop_back();
      used[static_cast<std::size_t>(to)] = false;
    }
  };
  dfs(kInitialTrajectory, start_s, 0.0);
  best.reaching_trajectories = count;
  return best;
}

TaskOrder TaskOrderer::dynamic_programming(double start_s) const {
  // State (set of done tasks, last task) -> earliest time the last task is
  // done. States are visited by increasing set size, so every predecessor of
  // a state is final before the state extends.
  const int n = size();
  if (n > kMaxDpTasks)
    throw std::invalid_argument("TaskOrderer::dynamic_programming: more than " +
                                std::to_string(kMaxDpTasks) + " tasks");
  TaskOrder r;
  if (n == 0) {
    r.feasible = true;
    r.total_time_s = r.moving_time_s = 0.0;
    return r;
  }
  const std::size_t masks = std::size_t{1} << n;
  const auto idx = [n](std::size_t mask, int last) {
    return mask * static_cast<std::size_t>(n) + static_cast<std::size_t>(last);
  };
  std::vector<double> done(masks * static_cast<std::size_t>(n), kInf);
  std::vector<double> moved(done.size(), kInf);
  std::vector<int> parent(done.size(), -2);
  std::int64_t count = 0;
  for (int to = 0; to < n; ++to) {
    const double d = reach(kInitialTrajectory, to, start_s, &count);
    if (!std::isfinite(d)) continue;
    const std::size_t k = idx(std::size_t{1} << to, to);
    done[k] = start_s + d + hold_s_[static_cast<std::size_t>(to)];
    moved[k] = d;
    parent[k] = kInitialTrajectory;
  }
  std::vector<std::size_t> order_masks(masks);
  for (std::size_t m = 0; m < masks; ++m) order_masks[m] = m;
  std::stable_sort(order_masks.begin(), order_masks.end(), [](std::size_t a, std::size_t b) {
    return __builtin_popcountll(a) < __builtin_popcountll(b);
  });
  for (std::size_t mask : order_masks) {
    if (mask == 0 || mask == masks - 1) continue;
    for (int last = 0; last < n; ++last) {
      const double t = done[idx(mask, last)];
      if (!std::isfinite(t)) continue;
      for (int to = 0; to < n; ++to) {
        if (mask & (std::size_t{1} << to)) continue;
        const double d = reach(last, to, t, &count);
        if (!std::isfinite(d)) continue;
        const std::size_t k = idx(mask | (std::size_t{1} << to), to);
        const double t_done = t + d + hold_s_[static_cast<std::size_t>(to)];
        if (t_done < done[k]) {
          done[k] = t_done;
          moved[k] = moved[idx(mask, last)] + d;
          parent[k] = last;
        }
      }
    }
  }
  r.reaching_trajectories = count;
  int last = -1;
  double best = kInf;
  for (int j = 0; j < n; ++j) {
    if (done[idx(masks - 1, j)] < best) best = done[idx(masks - 1, j)], last = j;
  }
  if (last < 0) return r;
  r.feasible = true;
  r.total_time_s = best - start_s;
  r.moving_time_s = moved[idx(masks - 1, last)];
  std::size_t mask = masks - 1;
  std::vector<int> rev;
  while (last >= 0) {
    rev.push_back(last);
    const int p = parent[idx(mask, last)];
    mask &= ~(std::size_t{1} << last);
    last = p;
  }
  r.order.assign(rev.rbegin(), rev.rend());
  // Times along the chosen order, from the kept states (no new trajectories).
  mask = 0;
  double t = start_s;
  for (int j : r.order) {
    mask |= std::size_t{1} << j;
    const double t_done = done[idx(mask, j)];
    const double arrive = t_done - hold_s_[static_cast<std::size_t>(j)];
    r.launch_s.push_back(t);
    r.arrival_s.push_back(arrive);
    r.done_s.push_back(t_done);
    t = t_done;
  }
  return r;
}

TaskOrder TaskOrderer::order(OrderingMethod m, double start_s) const {
  switch (m) {
    case OrderingMethod::kGreedy:
      return greedy(start_s);
    case OrderingMethod::kExhaustive:
      return exhaustive(start_s);
    case OrderingMethod::kDynamicProgramming:
      return dynamic_programming(start_s);
  }
  throw std::invalid_argument("TaskOrderer::order: unknown method");
}

std::int64_t TaskOrderer::greedy_count(int n) { return std::int64_t{n} * (n + 1) / 2; }

std::int64_t TaskOrderer::exhaustive_count(int n) {
  std::int64_t sum = 0;
  for (int k = 1; k <= n; ++k) sum += factorial(n) / factorial(n - k);
  return sum;
}

std::int64_t TaskOrderer::dp_count(int n) {
  if (n <= 0) return 0;
  if (n == 1) return 1;
  return n + std::int64_t{n} * (n - 1) * (std::int64_t{1} << (n - 2));
}

std::int64_t TaskOrderer::paper_exhaustive_count(int n) {
  std::int64_t sum = 0;
  for (int i = 1; i <= n; ++i) sum += factorial(n) / factorial(i - 1);
  return sum;
}

std::int64_t TaskOrderer::paper_dp_count(int n) {
  std::int64_t sum = 0;
  for (int i = 1; i <= n; ++i) sum += factorial(n) / (factorial(n - i) * factorial(i - 1));
  return sum;
}

}  // namespace ephor::rambo
