#pragma once
// Scheduler: the user-level scheduler of one host (paper 003, section 3.1),
// as pure logic. The process (main.cc) feeds it task registrations and job
// statistics from LCM and publishes what it decides.
//
// It owns the host's task table, gives every task a CPU (pinned, or first-fit
// decreasing for "auto"), a policy and a rate-monotonic priority, keeps the
// newest execution times of every task (percentiles over `history` jobs; the
// paper's three-run estimate for utilisation, on CPU time so that
// preemption by others does not look like demand), and when a CPU's measured
// utilisation passes its schedulable bound it moves an "auto" task to a CPU
// where it fits and says why.

#include <sys/types.h>

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "common/runtime/rolling_stats.h"
#include "common/runtime/thread_sched.h"
#include "procs/shared/scheduler/task_table.h"

namespace ephor::scheduler {

struct SchedulerConfig {
  std::vector<int> cpus;       // CPUs tasks may use
  double fixed_bound = 0.0;    // 0 = Liu & Layland
  size_t history = 1000;       // jobs kept for percentiles
  size_t estimate_window = 3;  // newest jobs whose max is the execution estimate
  int fifo_priority_max = 80;
  bool migrate = true;
  int64_t migrate_holdoff_us = 5'000'000;  // a task is not moved again within this time
  int64_t alive_timeout_us = 3'000'000;    // not heard from within this: not alive
};

struct Registration {
  std::string process, task;
  int pid = 0, tid = 0;
  bool periodic = true;
  int64_t period_us = 0, deadline_us = 0;
};

struct JobSample {
  int32_t start_latency_us = 0;
  int32_t exec_us = 0;  // wall time from start to end
  int32_t cpu_us = -1;  // CPU time of the job (its demand); -1 = unknown, use exec_us
  bool deadline_met = true;
  int32_t skipped_releases = 0;
};

struct JobsReport {
  std::string process, task;
  int pid = 0, tid = 0;
  bool rt_granted = false;
  std::string rt_error;
  int32_t generation = -1;
  std::vector<JobSample> jobs;
};

struct Assignment {
  std::string process, task;
  int cpu = -1;
  Policy policy = Policy::kOther;
  int priority = 0;
  int64_t period_us = 0, deadline_us = 0;
  int32_t generation = 0;
};

struct TaskStatus {
  Assignment assignment;
  bool in_table = true;  // false: registered but not in the manifest
  bool registered = false;
  bool alive = false;
  int pid = 0, tid = 0;
  bool periodic = true;
  SchedReadback readback;                           // what the kernel says the thread runs with
  double exec_p50 = 0, exec_p99 = 0, exec_max = 0;  // us
  double jitter_p50 = 0, jitter_p99 = 0, jitter_max = 0;  // us
  int64_t jobs = 0, deadline_misses = 0;
  double utilisation = 0;
  bool rt_granted = false;  // FIFO asked for and in force
  std::string rt_error;
};

struct HostStatus {
  std::vector<int> cpus;
  std::vector<double> cpu_utilisation;
  std::vector<double> cpu_bound;
  std::vector<TaskStatus> tasks;
  bool rt = true;  // every live task that asked for SCHED_FIFO has it
};

class Scheduler {
 public:
  // `readback` reads a thread's real scheduling state (read_thread_sched in
  // production; a fake in tests).
  Scheduler(SchedulerConfig config, std::vector<TaskEntry> table,
            std::function<SchedReadback(pid_t)> readback = read_thread_sched);

  void on_register(const Registration& reg, int64_t now_us);
  void on_jobs(const JobsReport& report, int64_t now_us);

  // Measures utilisation and, when allowed, moves at most one task off an
  // overloaded CPU. Returns human-readable events (also kept in events()).
  std::vector<std::string> rebalance(int64_t now_us);

  std::vector<Assignment> assignments() const;
  HostStatus status(int64_t now_us) const;
  // Events since construction, newest last (at most 20 kept).
  const std::vector<std::string>& events() const { return events_; }
  // New SCHED_FIFO refusals since the last call ("process/task: reason").
  std::vector<std::string> take_new_refusals();

 private:
  struct Row {
    TaskEntry entry;
    bool in_table = true;
    Assignment assignment;
    Registration reg;
    bool registered = false;
    int64_t last_heard_us = 0;
    int64_t last_migrated_us = -1'000'000'000'000;
    RollingStats exec;
    RollingStats jitter;
    RollingStats demand;  // CPU time per job: what utilisation is estimated from
    int64_t jobs = 0;
    int64_t misses = 0;
    int64_t jobs_in_window = 0;  // jobs since the last rebalance (rate of triggered tasks)
    double rate_hz = 0.0;
    bool rt_granted = false;
    bool refusal_reported = false;
    std::string rt_error;
    Row(TaskEntry e, size_t history)
        : entry(std::move(e)), exec(history), jitter(history), demand(history) {}
  };

  Row& row_for(const std::string& process, const std::string& task, bool periodic,
               int64_t period_us, int64_t deadline_us);
  double utilisation(const Row& row) const;
  void add_event(std::string event);

  SchedulerConfig config_;
  std::vector<Row> rows_;
  std::function<SchedReadback(pid_t)> readback_;
  std::vector<std::string> events_;
  std::vector<std::string> new_refusals_;
  int64_t last_rebalance_us_ = 0;
};

}  // namespace ephor::scheduler
