#include "common/display/sched_status_rows.h"

#include <utility>

namespace ephor::display {

HostSched host_sched_of(const sched_status_t& m) {
  HostSched h;
  h.host = m.host;
  h.rt = m.rt != 0;
  for (float x : m.cpu_utilisation) h.cpu_utilisation.push_back(static_cast<double>(x));
  for (float x : m.cpu_bound) h.cpu_bound.push_back(static_cast<double>(x));
  for (const auto& t : m.tasks) {
    TaskRow r;
    r.process = t.process;
    r.task = t.task;
    r.policy = t.policy;
    r.cpu = t.cpu;
    r.priority = t.priority;
    r.periodic = t.periodic != 0;
    r.rt_granted = t.rt_granted != 0;
    r.alive = t.alive != 0;
    r.period_us = t.period_us;
    r.deadline_us = t.deadline_us;
    r.jobs = t.jobs;
    r.deadline_misses = t.deadline_misses;
    r.exec_p50_us = static_cast<double>(t.exec_p50_us);
    r.exec_p99_us = static_cast<double>(t.exec_p99_us);
    r.exec_max_us = static_cast<double>(t.exec_max_us);
    r.jitter_p50_us = static_cast<double>(t.jitter_p50_us);
    r.jitter_p99_us = static_cast<double>(t.jitter_p99_us);
    r.jitter_max_us = static_cast<double>(t.jitter_max_us);
    r.utilisation = static_cast<double>(t.utilisation);
    h.tasks.push_back(std::move(r));
  }
  h.events = m.events;
  return h;
}

}  // namespace ephor::display
