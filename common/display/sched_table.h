#pragma once
// SchedTable: the scheduler's task table as every display page shows it: the
// newest EPHOR_SCHED_STATUS (sched_status_t) of each host, as plain structs
// (DisplayServer converts the messages), in the JSON the pages draw
// ("sched": one entry per host, its tasks, CPU use and events).
//
// Not thread-safe: DisplayServer holds its lock around every call.

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace ephor::display {

struct TaskRow {
  std::string process, task, policy;
  int cpu = -1, priority = 0;
  bool periodic = false, rt_granted = false, alive = false;
  int64_t period_us = 0, deadline_us = 0, jobs = 0, deadline_misses = 0;
  double exec_p50_us = 0, exec_p99_us = 0, exec_max_us = 0;
  double jitter_p50_us = 0, jitter_p99_us = 0, jitter_max_us = 0;
  double utilisation = 0;
};

struct HostSched {
  std::string host;
  bool rt = false;
  std::vector<double> cpu_utilisation, cpu_bound;
  std::vector<TaskRow> tasks;
  std::vector<std::string> events;
};

class SchedTable {
 public:
  // Replaces the host's previous status.
  void on_sched(HostSched host);
  // An array of hosts in name order, each {host, rt, cpu_utilisation, cpu_bound, tasks, events}.
  nlohmann::json to_json() const;
  size_t hosts() const { return hosts_.size(); }

 private:
  std::map<std::string, HostSched> hosts_;
};

}  // namespace ephor::display
