#include "procs/shared/scheduler/task_messages.h"

namespace ephor::scheduler {

std::optional<Registration> registration_of(const task_register_t& m, const std::string& host) {
  if (m.host != host) return std::nullopt;
  return Registration{m.process, m.task, m.pid, m.tid, m.periodic != 0, m.period_us, m.deadline_us};
}

std::optional<JobsReport> jobs_report_of(const task_jobs_t& m, const std::string& host) {
  if (m.host != host) return std::nullopt;
  JobsReport r;
  r.process = m.process;
  r.task = m.task;
  r.pid = m.pid;
  r.tid = m.tid;
  r.rt_granted = m.rt_granted;
  r.rt_error = m.rt_error;
  r.generation = m.generation;
  for (const auto& j : m.jobs)
    r.jobs.push_back(
        {j.start_latency_us, j.exec_us, j.cpu_us, j.deadline_met != 0, j.skipped_releases});
  return r;
}

}  // namespace ephor::scheduler
