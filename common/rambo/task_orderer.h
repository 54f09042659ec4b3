#pragma once
// The order of a set of tasks on a moving target (RAMBO paper, section 10):
// greedy, exhaustive search and dynamic programming.
//
// A task is "bring the tagging joint onto goal point i's predicted trajectory
// and hold it there for hold_s". The time a move takes depends on where the
// tool is (which goal trajectory it follows, or its initial trajectory) and
// on when it launches, because the target keeps moving. So the cost is a
// callback, ReachingDurationFn, that in the planner computes one reaching
// trajectory (section 9's shortest duration T); each method counts how many
// it computes, which is the quantity the paper compares.
//
// Count formulas (n tasks, every move feasible):
//   greedy       sum_{k=1..n} k                      = n(n+1)/2             (4 tasks: 10)
//   exhaustive   sum_{k=1..n} n!/(n-k)!              (prefix tree: a move
//                is computed once per distinct ordered prefix) = the paper's
//                sum_{i=1..n} n!/(i-1)!  (i = n-k+1)                      (4 tasks: 64)
//   DP computed  n + sum_{k=1..n-1} k C(n,k) (n-k)   = n + n(n-1) 2^(n-2)   (4 tasks: 52)
//   DP states    sum_{i=1..n} n!/((n-i)!(i-1)!)      = sum_i i C(n,i) = n 2^(n-1) (4 tasks: 32)
// The paper's 32 for DP is the number of states (set of done tasks, last
// task): one *kept* best reaching trajectory per state. To find each state's
// best trajectory, the DP must compute one reaching trajectory per
// predecessor (a state with k done tasks has k-1 predecessors, the first
// moves one), which is n + n(n-1)2^(n-2): 52 for four tasks, not 32. The
// paper's exhaustive figure (64) does count computed trajectories, and
// matches ours when prefixes are shared (without sharing it is n*n! = 96).
//
// When DP is exact: DP keeps, per state, only the earliest time the last
// task is done. That is optimal when arriving later never lets a move finish
// earlier (launch + T(launch) non-decreasing in launch, "FIFO" or
// no-overtaking; true when T changes slower than time, |dT/dt| < 1, or when
// the tool may wait on its goal trajectory). Otherwise exhaustive search is
// the exact one and DP a heuristic; the tests use costs that satisfy FIFO.

#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

namespace ephor::rambo {

// Reaching duration in s for moving the tagging joint onto task `to`'s goal
// trajectory, launched at `launch_s` (s, the planner's clock) from task
// `from`'s goal trajectory, or from the tool's initial trajectory when
// from == kInitialTrajectory. +inf (or NaN) when no reaching trajectory
// exists. Called from the caller's thread only.
using ReachingDurationFn = std::function<double(int from, int to, double launch_s)>;

enum class OrderingMethod { kGreedy, kExhaustive, kDynamicProgramming };
const char* to_string(OrderingMethod m);

struct TaskOrder {
  bool feasible = false;          // every task reached
  std::vector<int> order;         // task indices in execution order
  std::vector<double> launch_s;   // when each reaching trajectory starts, s
  std::vector<double> arrival_s;  // when the tool lands on the goal trajectory, s
  std::vector<double> done_s;     // arrival + hold, s
  double total_time_s = std::numeric_limits<double>::infinity();   // last done - start
  double moving_time_s = std::numeric_limits<double>::infinity();  // sum of reaching durations
  std::int64_t reaching_trajectories = 0;  // callback calls (trajectories computed)
};

class TaskOrderer {
 public:
  static constexpr int kInitialTrajectory = -1;
  static constexpr int kMaxExhaustiveTasks = 10;  // 10! orders: beyond that use DP
  static constexpr int kMaxDpTasks = 20;          // 2^20 * 20 states

  // hold_s[i]: how long task i holds its goal trajectory, s (>= 0, finite).
  // Throws std::invalid_argument on a bad hold time or an empty callback.
  TaskOrderer(std::vector<double> hold_s, ReachingDurationFn reaching_duration);

  int size() const { return static_cast<int>(hold_s_.size()); }

  // Each method starts with the tool on its initial trajectory at start_s.
  TaskOrder greedy(double start_s) const;
  TaskOrder exhaustive(double start_s) const;
  TaskOrder dynamic_programming(double start_s) const;
  TaskOrder order(OrderingMethod m, double start_s) const;

  // The times of a given order (n reaching trajectories); for checks.
  TaskOrder evaluate(const std::vector<int>& order, double start_s) const;

  // The formulas above (every move feasible).
  static std::int64_t greedy_count(int n);
  static std::int64_t exhaustive_count(int n);        // sum n!/(n-k)!
  static std::int64_t dp_count(int n);                // n + n(n-1)2^(n-2)
  static std::int64_t paper_exhaustive_count(int n);  // sum_{i} n!/(i-1)!, as printed
  static std::int64_t paper_dp_count(int n);          // sum_{i} n!/((n-i)!(i-1)!), as printed

 private:
  double reach(int from, int to, double launch_s, std::int64_t* count) const;

  std::vector<double> hold_s_;
  ReachingDurationFn reaching_duration_;
};

}  // namespace ephor::rambo
