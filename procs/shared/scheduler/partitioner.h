#pragma once
// Partitioning tasks onto CPUs (pure functions, unit-tested).
//
// Each CPU runs its tasks under fixed priorities (rate-monotonic), so a CPU's
// task set is taken as schedulable while its total utilisation stays within
// the Liu & Layland bound n (2^(1/n) - 1) for its n tasks (or a configured
// fixed bound).

#include <optional>
#include <string>
#include <vector>

namespace ephor::scheduler {

// Liu & Layland's rate-monotonic bound for n tasks (1.0 for n <= 1).
double liu_layland_bound(int n);

struct PartitionItem {
  double utilisation = 0.0;  // exec / period
  int pinned_cpu = -1;       // -1 = the partitioner chooses
};

struct Partition {
  std::vector<int> cpu_of;              // per item, an index into `cpus`' values
  std::vector<double> cpu_utilisation;  // per CPU (same order as `cpus`)
  std::vector<int> cpu_tasks;           // number of tasks per CPU
  bool feasible = true;                 // every CPU within its bound
};

// Bound for a CPU with n tasks: `fixed_bound` when > 0, else Liu & Layland.
double cpu_bound(int n, double fixed_bound);

// First-fit decreasing: pinned items go to their CPU; the others, largest
// utilisation first, go to the first CPU (in `cpus` order) where they fit
// within the bound; an item that fits nowhere goes to the least-loaded CPU
// and the partition is marked infeasible. `cpus` holds CPU numbers.
Partition first_fit_decreasing(const std::vector<PartitionItem>& items,
                               const std::vector<int>& cpus, double fixed_bound);

struct Migration {
  size_t item = 0;
  int from_cpu = -1;
  int to_cpu = -1;
  std::string reason;
};

// When a CPU is over its bound, picks one movable (not pinned) item on it to
// move to another CPU where it fits: the largest one that fits anywhere,
// preferring the least-loaded destination. `cpu_of` holds current CPU
// numbers; `movable[i]` false for pinned items. nullopt when nothing is
// overloaded or nothing can move.
std::optional<Migration> plan_migration(const std::vector<double>& utilisation,
                                        const std::vector<int>& cpu_of,
                                        const std::vector<bool>& movable,
                                        const std::vector<int>& cpus, double fixed_bound);

}  // namespace ephor::scheduler
