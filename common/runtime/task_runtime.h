#pragma once
// TaskRuntime: the modern BEGIN_PROC / END_PROC of the Ephor paper (section
// 3.1). A process declares its tasks; each runs on its own thread (the
// paper's light-weight processes) and each job is released either
// periodically (absolute-time clock_nanosleep on CLOCK_MONOTONIC) or by a
// trigger (the paper's to_do[goal] = 1: trigger() here, or a task_trigger_t
// from any process).
//
// The runtime registers every task with its host's ephor-scheduler, applies
// the CPU, policy, priority and period the scheduler assigns at the start of
// the next job (also when the assignment changes at run time: the paper's
// migrate flag), locks memory, and publishes per-job statistics (release
// time, start latency, execution time, deadline met) in batches.
//
// Threads: job functions run on their task's thread; only one job of a task
// runs at a time. Bus callbacks run on the bus thread, which the runtime
// starts.

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "common/lcm/bus.h"
#include "common/runtime/thread_sched.h"

namespace ephor {

struct RuntimeOptions {
  std::string process;      // this process's name (manifest name)
  std::string host;         // host name; the runtime follows only this host's scheduler
  bool lock_memory = true;  // mlockall at start(); a refusal is a warning
};

// Statistics of one task as kept by the runtime (for tests and logs).
struct TaskCounters {
  int64_t jobs = 0;
  int64_t deadline_misses = 0;
  int64_t skipped_releases = 0;
  int64_t merged_triggers = 0;  // triggers that arrived while a job was already pending
  int32_t generation = -1;      // assignment generation applied, -1 = none yet
  bool rt_granted = false;
};

class TaskRuntime {
 public:
  using Job = std::function<void()>;
  using Ns = std::chrono::nanoseconds;

  TaskRuntime(Bus& bus, RuntimeOptions options);
  ~TaskRuntime();
  TaskRuntime(const TaskRuntime&) = delete;
  TaskRuntime& operator=(const TaskRuntime&) = delete;

  // Declares a task released every `period`; deadline 0 = the period. The
  // scheduler may later assign another period. Call before start().
  void add_periodic(const std::string& task, Ns period, Job job, Ns deadline = Ns(0));
  // Declares a task released by triggers; a trigger that arrives while a job
  // is already pending is merged into it (to_do[] is a flag).
  void add_triggered(const std::string& task, Ns deadline, Job job);

  // Releases one job of a triggered task of this process. Any thread.
  void trigger(const std::string& task);

  // Locks a periodic task's release phase to an external event: after its
  // current job, the task is released at anchor_mono_ns + k * period (the
  // first such time after the job ends). Call on every event (e.g. each
  // camera frame's arrival plus a small lag) to keep the phase locked. Any
  // thread.
  void align_release(const std::string& task, int64_t anchor_mono_ns);

  // Locks memory, subscribes to the scheduler, starts the bus thread and one
  // thread per task.
  void start();
  // Stops every task after its current job, joins the threads and stops
  // the bus thread that start() started.
  void stop();

  TaskCounters counters(const std::string& task) const;

 private:
  struct Task;
  void task_main(Task& task);
  void housekeeping_main();
  void apply_pending(Task& task);
  void publish_jobs(Task& task, bool even_if_empty);
  void publish_register(Task& task);
  Task* find(const std::string& name) const;

  Bus& bus_;
  RuntimeOptions options_;
  std::vector<std::unique_ptr<Task>> tasks_;
  bool started_ = false;
  std::mutex stop_mutex_;
  std::condition_variable stop_cv_;
  bool stopping_ = false;
  std::thread housekeeping_;
};

}  // namespace ephor
