#include "procs/shared/scheduler/scheduler.h"

#include <algorithm>

#include "procs/shared/scheduler/partitioner.h"

namespace ephor::scheduler {

Scheduler::Scheduler(SchedulerConfig config, std::vector<TaskEntry> table,
                     std::function<SchedReadback(pid_t)> readback)
    : config_(std::move(config)), readback_(std::move(readback)) {
  if (config_.cpus.empty()) config_.cpus.push_back(0);
  assign_rate_monotonic(table, config_.fifo_priority_max);

  // Initial placement: first-fit decreasing on the manifest's expected
  // utilisation (zero when not given: measured values take over at run time).
  std::vector<PartitionItem> items;
  for (const auto& e : table) items.push_back({e.expected_utilisation, e.cpu});
  const Partition p = first_fit_decreasing(items, config_.cpus, config_.fixed_bound);
  for (size_t i = 0; i < table.size(); ++i) {
    Row row(table[i], config_.history);
    row.assignment.process = table[i].process;
    row.assignment.task = table[i].task;
    row.assignment.cpu = p.cpu_of[i];
    row.assignment.policy = table[i].fifo ? Policy::kFifo : Policy::kOther;
    row.assignment.priority = table[i].priority;
    row.assignment.period_us = table[i].period_us;
    row.assignment.deadline_us = table[i].deadline_us;
    row.assignment.generation = 1;
    rows_.push_back(std::move(row));
  }
}

Scheduler::Row& Scheduler::row_for(const std::string& process, const std::string& task,
                                   bool periodic, int64_t period_us, int64_t deadline_us) {
  for (auto& r : rows_)
    if (r.entry.process == process && r.entry.task == task) return r;
  // Not in the manifest: schedule it politely (SCHED_OTHER, any CPU) and say so.
  TaskEntry e;
  e.process = process;
  e.task = task;
  e.periodic = periodic;
  e.period_us = period_us;
  e.deadline_us = deadline_us;
  e.fifo = false;
  Row row(e, config_.history);
  row.in_table = false;
  row.assignment.process = process;
  row.assignment.task = task;
  row.assignment.cpu = -1;
  row.assignment.policy = Policy::kOther;
  row.assignment.generation = 1;
  rows_.push_back(std::move(row));
  add_event("task " + process + "/" + task +
            " is not in the task table: running it under SCHED_OTHER on any CPU");
  return rows_.back();
}

void Scheduler::on_register(const Registration& reg, int64_t now_us) {
  Row& row = row_for(reg.process, reg.task, reg.periodic, reg.period_us, reg.deadline_us);
  if (!row.registered || row.reg.pid != reg.pid || row.reg.tid != reg.tid) {
    if (row.registered && row.reg.pid != reg.pid) {
      add_event("task " + row.entry.key() + " restarted (pid " + std::to_string(row.reg.pid) +
                " -> " + std::to_string(reg.pid) + ")");
      row.exec.clear();
      row.jitter.clear();
      row.demand.clear();
      row.refusal_reported = false;
    }
  }
  row.reg = reg;
  row.registered = true;
  row.last_heard_us = now_us;
}

void Scheduler::on_jobs(const JobsReport& report, int64_t now_us) {
  Row& row = row_for(report.process, report.task, true, 0, 0);
  row.last_heard_us = now_us;
  if (!row.registered && report.tid > 0) {
    row.reg.process = report.process;
    row.reg.task = report.task;
    row.reg.pid = report.pid;
    row.reg.tid = report.tid;
    row.reg.periodic = row.entry.periodic;
    row.registered = true;
  }
  for (const JobSample& j : report.jobs) {
    row.exec.add(j.exec_us);
    row.demand.add(j.cpu_us >= 0 ? j.cpu_us : j.exec_us);
    row.jitter.add(j.start_latency_us);
    ++row.jobs;
    ++row.jobs_in_window;
    if (!j.deadline_met) ++row.misses;
    row.misses += j.skipped_releases;
  }
  // Only the current assignment's outcome counts (an older generation may
  // still be in flight).
  if (report.generation == row.assignment.generation) {
    row.rt_granted = report.rt_granted;
    row.rt_error = report.rt_error;
    if (row.assignment.policy == Policy::kFifo && !report.rt_granted && !row.refusal_reported) {
      row.refusal_reported = true;
      new_refusals_.push_back(row.entry.key() + ": " + report.rt_error);
    }
  }
}

double Scheduler::utilisation(const Row& row) const {
  if (row.demand.empty()) return row.entry.expected_utilisation;
  const double est_us = row.demand.max_of_newest(config_.estimate_window);
  if (row.entry.periodic && row.assignment.period_us > 0)
    return est_us / static_cast<double>(row.assignment.period_us);
  // Triggered: cost times the measured release rate.
  return est_us * 1e-6 * row.rate_hz;
}

std::vector<std::string> Scheduler::rebalance(int64_t now_us) {
  const double window_s =
      last_rebalance_us_ > 0 ? static_cast<double>(now_us - last_rebalance_us_) * 1e-6 : 0.0;
  last_rebalance_us_ = now_us;
  for (auto& r : rows_) {
    if (window_s > 0.0) r.rate_hz = static_cast<double>(r.jobs_in_window) / window_s;
    r.jobs_in_window = 0;
  }
  std::vector<std::string> out;
  if (!config_.migrate) return out;

  std::vector<double> util;
  std::vector<int> cpu_of;
  std::vector<bool> movable;
  for (const auto& r : rows_) {
    const bool live = r.registered && now_us - r.last_heard_us <= config_.alive_timeout_us;
    util.push_back(live ? utilisation(r) : 0.0);
    cpu_of.push_back(r.assignment.cpu);
    movable.push_back(r.in_table && r.entry.cpu < 0 && live &&
                      now_us - r.last_migrated_us >= config_.migrate_holdoff_us);
  }
  const auto m = plan_migration(util, cpu_of, movable, config_.cpus, config_.fixed_bound);
  if (m) {
    Row& r = rows_[m->item];
    r.assignment.cpu = m->to_cpu;
    r.assignment.generation += 1;
    r.last_migrated_us = now_us;
    std::string event = "migrating " + r.entry.key() + " from CPU " + std::to_string(m->from_cpu) +
                        " to CPU " + std::to_string(m->to_cpu) + ": " + m->reason;
    add_event(event);
    out.push_back(event);
  }
  return out;
}

std::vector<Assignment> Scheduler::assignments() const {
  std::vector<Assignment> out;
  for (const auto& r : rows_) out.push_back(r.assignment);
  return out;
}

HostStatus Scheduler::status(int64_t now_us) const {
  HostStatus hs;
  hs.cpus = config_.cpus;
  hs.cpu_utilisation.assign(config_.cpus.size(), 0.0);
  std::vector<int> count(config_.cpus.size(), 0);
  for (const auto& r : rows_) {
    TaskStatus ts;
    ts.assignment = r.assignment;
    ts.in_table = r.in_table;
    ts.registered = r.registered;
    ts.alive = r.registered && now_us - r.last_heard_us <= config_.alive_timeout_us;
    ts.pid = r.reg.pid;
    ts.tid = r.reg.tid;
    ts.periodic = r.entry.periodic;
    if (ts.alive && r.reg.tid > 0) ts.readback = readback_(r.reg.tid);
    ts.exec_p50 = r.exec.percentile(50);
    ts.exec_p99 = r.exec.percentile(99);
    ts.exec_max = r.exec.max();
    ts.jitter_p50 = r.jitter.percentile(50);
    ts.jitter_p99 = r.jitter.percentile(99);
    ts.jitter_max = r.jitter.max();
    ts.jobs = r.jobs;
    ts.deadline_misses = r.misses;
    ts.utilisation = ts.alive ? utilisation(r) : 0.0;
    const bool wants_fifo = r.assignment.policy == Policy::kFifo;
    ts.rt_granted =
        wants_fifo && r.rt_granted && (!ts.readback.ok || ts.readback.policy == Policy::kFifo);
    ts.rt_error = r.rt_error;
    if (ts.alive && wants_fifo && !ts.rt_granted) hs.rt = false;
    const auto it = std::find(config_.cpus.begin(), config_.cpus.end(), r.assignment.cpu);
    if (it != config_.cpus.end() && ts.alive) {
      const size_t c = static_cast<size_t>(it - config_.cpus.begin());
      hs.cpu_utilisation[c] += ts.utilisation;
      count[c] += 1;
    }
    hs.tasks.push_back(std::move(ts));
  }
  for (size_t c = 0; c < config_.cpus.size(); ++c)
    hs.cpu_bound.push_back(cpu_bound(count[c], config_.fixed_bound));
  return hs;
}

std::vector<std::string> Scheduler::take_new_refusals() {
  std::vector<std::string> out;
  out.swap(new_refusals_);
  return out;
}

void Scheduler::add_event(std::string event) {
  events_.push_back(std::move(event));
  if (events_.size() > 20) events_.erase(events_.begin());
}

}  // namespace ephor::scheduler
