#include "procs/shared/scheduler/partitioner.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>

namespace ephor::scheduler {

double liu_layland_bound(int n) {
  if (n <= 1) return 1.0;
  return n * (std::pow(2.0, 1.0 / n) - 1.0);
}

double cpu_bound(int n, double fixed_bound) {
  return fixed_bound > 0.0 ? fixed_bound : liu_layland_bound(n);
}

Partition first_fit_decreasing(const std::vector<PartitionItem>& items,
                               const std::vector<int>& cpus, double fixed_bound) {
  Partition p;
  p.cpu_of.assign(items.size(), cpus.empty() ? -1 : cpus.front());
  p.cpu_utilisation.assign(cpus.size(), 0.0);
  p.cpu_tasks.assign(cpus.size(), 0);
  if (cpus.empty()) {
    p.feasible = items.empty();
    return p;
  }
  auto index_of = [&](int cpu) {
    auto it = std::find(cpus.begin(), cpus.end(), cpu);
    return it == cpus.end() ? -1 : static_cast<int>(it - cpus.begin());
  };
  std::vector<size_t> order(items.size());
  std::iota(order.begin(), order.end(), 0);
  // Pinned first, then the rest by decreasing utilisation (stable: ties keep
  // manifest order, so the result is deterministic).
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    const bool pa = items[a].pinned_cpu >= 0, pb = items[b].pinned_cpu >= 0;
    if (pa != pb) return pa;
    return items[a].utilisation > items[b].utilisation;
  });
  for (size_t i : order) {
    const auto& item = items[i];
    int slot = item.pinned_cpu >= 0 ? index_of(item.pinned_cpu) : -1;
    if (item.pinned_cpu >= 0 && slot < 0) {
      // Pinned to a CPU the scheduler may not use: keep the pin (the runtime
      // reports the refusal) but it counts against no CPU here.
      p.cpu_of[i] = item.pinned_cpu;
      p.feasible = false;
      continue;
    }
    if (slot < 0) {
      for (size_t c = 0; c < cpus.size(); ++c) {
        if (p.cpu_utilisation[c] + item.utilisation <= cpu_bound(p.cpu_tasks[c] + 1, fixed_bound)) {
          slot = static_cast<int>(c);
          break;
        }
      }
    }
    if (slot < 0) {
      slot = static_cast<int>(std::min_element(p.cpu_utilisation.begin(), p.cpu_utilisation.end()) -
                              p.cpu_utilisation.begin());
    }
    p.cpu_of[i] = cpus[static_cast<size_t>(slot)];
    p.cpu_utilisation[static_cast<size_t>(slot)] += item.utilisation;
    p.cpu_tasks[static_cast<size_t>(slot)] += 1;
  }
  for (size_t c = 0; c < cpus.size(); ++c)
    if (p.cpu_utilisation[c] > cpu_bound(p.cpu_tasks[c], fixed_bound)) p.feasible = false;
  return p;
}

std::optional<Migration> plan_migration(const std::vector<double>& utilisation,
                                        const std::vector<int>& cpu_of,
                                        const std::vector<bool>& movable,
                                        const std::vector<int>& cpus, double fixed_bound) {
  std::vector<double> load(cpus.size(), 0.0);
  std::vector<int> count(cpus.size(), 0);
  auto slot_of = [&](int cpu) {
    auto it = std::find(cpus.begin(), cpus.end(), cpu);
    return it == cpus.end() ? -1 : static_cast<int>(it - cpus.begin());
  };
  for (size_t i = 0; i < cpu_of.size(); ++i) {
    const int s = slot_of(cpu_of[i]);
    if (s < 0) continue;
    load[static_cast<size_t>(s)] += utilisation[i];
    count[static_cast<size_t>(s)] += 1;
  }
  for (size_t c = 0; c < cpus.size(); ++c) {
    const double bound = cpu_bound(count[c], fixed_bound);
    if (load[c] <= bound) continue;
    // Candidates on the overloaded CPU, largest first.
    std::vector<size_t> cand;
    for (size_t i = 0; i < cpu_of.size(); ++i)
      if (movable[i] && cpu_of[i] == cpus[c]) cand.push_back(i);
    std::stable_sort(cand.begin(), cand.end(),
                     [&](size_t a, size_t b) { return utilisation[a] > utilisation[b]; });
    for (size_t i : cand) {
      int best = -1;
      for (size_t d = 0; d < cpus.size(); ++d) {
        if (d == c) continue;
        if (load[d] + utilisation[i] > cpu_bound(count[d] + 1, fixed_bound)) continue;
        if (best < 0 || load[d] < load[static_cast<size_t>(best)]) best = static_cast<int>(d);
      }
      if (best < 0) continue;
      char reason[160];
      std::snprintf(reason, sizeof reason, "CPU %d utilisation %.2f > bound %.2f (%d tasks)",
                    cpus[c], load[c], bound, count[c]);
      return Migration{i, cpus[c], cpus[static_cast<size_t>(best)], reason};
    }
  }
  return std::nullopt;
}

}  // namespace ephor::scheduler
