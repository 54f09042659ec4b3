#include "procs/shared/scheduler/task_table.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "common/config/manifest.h"

namespace ephor::scheduler {

std::vector<TaskEntry> build_task_table(const config::Manifest& manifest, const std::string& host) {
  std::vector<TaskEntry> table;
  for (const auto& proc : manifest.process()) {
    if (!host.empty() && proc.host() != host) continue;
    for (const auto& t : proc.task()) {
      TaskEntry e;
      e.process = proc.name();
      e.task = t.name();
      e.periodic = t.kind() == config::Task::PERIODIC;
      e.period_us = e.periodic ? std::llround(t.period_ms() * 1000.0) : 0;
      e.deadline_us = std::llround(t.deadline_ms() * 1000.0);
      e.fifo = t.policy() != config::Task::OTHER;
      e.priority = t.priority();
      e.explicit_priority = t.priority() > 0;
      e.cpu = task_cpu(t);
      const double span_ms = e.periodic ? t.period_ms() : t.deadline_ms();
      e.expected_utilisation = span_ms > 0.0 ? t.expected_exec_ms() / span_ms : 0.0;
      table.push_back(e);
    }
  }
  return table;
}

void assign_rate_monotonic(std::vector<TaskEntry>& table, int max_priority) {
  // Rate-monotonic for periodic tasks; deadline-monotonic for triggered ones
  // (their deadline stands in for the minimum inter-arrival time).
  auto span = [](const TaskEntry& e) { return e.periodic ? e.period_us : e.deadline_us; };
  std::vector<int64_t> spans;
  for (const auto& e : table)
    if (e.fifo && !e.explicit_priority) spans.push_back(span(e));
  std::sort(spans.begin(), spans.end());
  spans.erase(std::unique(spans.begin(), spans.end()), spans.end());
  std::map<int64_t, int> prio;
  for (size_t i = 0; i < spans.size(); ++i)
    prio[spans[i]] = std::max(1, max_priority - static_cast<int>(i));
  for (auto& e : table) {
    if (!e.fifo)
      e.priority = 0;
    else if (!e.explicit_priority)
      e.priority = prio[span(e)];
  }
}

}  // namespace ephor::scheduler
