#pragma once
// The task table of one host: the manifest's rows for the processes on that
// host, with rate-monotonic priorities filled in where none were given.

#include <cstdint>
#include <string>
#include <vector>

#include "common/config/manifest.pb.h"

namespace ephor::scheduler {

struct TaskEntry {
  std::string process;
  std::string task;
  bool periodic = true;
  int64_t period_us = 0;    // 0 for triggered tasks
  int64_t deadline_us = 0;  // relative deadline
  bool fifo = true;         // SCHED_FIFO wanted (else SCHED_OTHER)
  int priority = 0;         // SCHED_FIFO priority; filled by assign_rate_monotonic()
  bool explicit_priority = false;
  int cpu = -1;                       // pinned CPU, -1 = auto
  double expected_utilisation = 0.0;  // expected_exec / period before measurements

  std::string key() const { return process + "/" + task; }
};

// Rows of every process on `host` ("" = every host).
std::vector<TaskEntry> build_task_table(const config::Manifest& manifest, const std::string& host);

// Gives each FIFO task without an explicit priority a rate-monotonic one:
// shorter period (for triggered tasks: shorter deadline) = higher priority,
// starting at `max_priority` and stepping down by one per distinct period,
// never below 1.
void assign_rate_monotonic(std::vector<TaskEntry>& table, int max_priority);

}  // namespace ephor::scheduler
