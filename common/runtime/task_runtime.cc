#include "common/runtime/task_runtime.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <stdexcept>

#include <spdlog/spdlog.h>

#include "common/runtime/channels.h"
#include "common/runtime/periodic_release.h"
#include "common/time/clock.h"
#include "ephor/sched_assignments_t.hpp"
#include "ephor/task_jobs_t.hpp"
#include "ephor/task_register_t.hpp"
#include "ephor/task_trigger_t.hpp"

namespace ephor {
namespace {

// Warn once per process, not once per task or job: a refused SCHED_FIFO is a
// property of the host, and a wall of identical warnings hides other news.
std::atomic<bool> g_warned_rt{false};
std::atomic<bool> g_warned_affinity{false};

int64_t to_us(int64_t ns) { return ns / 1000; }

}  // namespace

struct TaskRuntime::Task {
  std::string name;
  bool periodic = false;
  int64_t period_ns = 0;
  int64_t deadline_ns = 0;
  Job job;
  std::thread thread;
  pid_t tid = 0;

  // Guarded by mutex: trigger state, the pending assignment and the batch of
  // job statistics not yet published.
  mutable std::mutex mutex;
  std::condition_variable cv;
  bool triggered = false;
  int64_t trigger_release_ns = 0;
  bool assignment_pending = false;
  task_assignment_t pending{};
  std::vector<task_job_t> batch;
  TaskCounters counters;
  int8_t policy = task_assignment_t::POLICY_OTHER;
  int32_t priority = 0;
  int32_t cpu = -1;
  std::string rt_error;
  bool stop = false;
  bool state_changed = false;  // assignment applied since the last published batch
  int64_t anchor_ns = 0;       // pending release anchor (align_release), 0 = none
};

TaskRuntime::TaskRuntime(Bus& bus, RuntimeOptions options)
    : bus_(bus), options_(std::move(options)) {
  if (options_.process.empty()) throw std::invalid_argument("TaskRuntime: process name is empty");
}

TaskRuntime::~TaskRuntime() { stop(); }

void TaskRuntime::add_periodic(const std::string& task, Ns period, Job job, Ns deadline) {
  if (started_) throw std::logic_error("TaskRuntime: add tasks before start()");
  if (period.count() <= 0) throw std::invalid_argument("task " + task + ": period must be > 0");
  if (find(task) != nullptr) throw std::invalid_argument("task " + task + " declared twice");
  auto t = std::make_unique<Task>();
  t->name = task;
  t->periodic = true;
  t->period_ns = period.count();
  t->deadline_ns = deadline.count() > 0 ? deadline.count() : period.count();
  t->job = std::move(job);
  tasks_.push_back(std::move(t));
}

void TaskRuntime::add_triggered(const std::string& task, Ns deadline, Job job) {
  if (started_) throw std::logic_error("TaskRuntime: add tasks before start()");
  if (deadline.count() <= 0) throw std::invalid_argument("task " + task + ": deadline must be > 0");
  if (find(task) != nullptr) throw std::invalid_argument("task " + task + " declared twice");
  auto t = std::make_unique<Task>();
  t->name = task;
  t->deadline_ns = deadline.count();
  t->job = std::move(job);
  tasks_.push_back(std::move(t));
}

TaskRuntime::Task* TaskRuntime::find(const std::string& name) const {
  for (const auto& t : tasks_)
    if (t->name == name) return t.get();
  return nullptr;
}

void TaskRuntime::trigger(const std::string& task) {
  Task* t = find(task);
  if (t == nullptr || t->periodic) {
    spdlog::warn("runtime: trigger for unknown or periodic task '{}' ignored", task);
    return;
  }
  {
    std::lock_guard<std::mutex> lock(t->mutex);
    if (t->triggered) {
      ++t->counters.merged_triggers;
    } else {
      t->triggered = true;
      t->trigger_release_ns = mono_ns();
    }
  }
  t->cv.notify_all();
}

void TaskRuntime::align_release(const std::string& task, int64_t anchor_mono_ns) {
  Task* t = find(task);
  if (t == nullptr || !t->periodic) return;
  std::lock_guard<std::mutex> lock(t->mutex);
  t->anchor_ns = anchor_mono_ns;
}

void TaskRuntime::start() {
  if (started_) return;
  started_ = true;
  if (options_.lock_memory) {
    const std::string err = lock_process_memory();
    if (!err.empty())
      spdlog::warn("runtime: cannot lock memory ({}); page faults may add latency", err);
  }

  bus_.subscribe<sched_assignments_t>(
      channels::kSchedAssign, [this](const sched_assignments_t& msg) {
        if (msg.host != options_.host) return;
        for (const auto& row : msg.tasks) {
          if (row.process != options_.process) continue;
          Task* t = find(row.task);
          if (t == nullptr) continue;
          {
            std::lock_guard<std::mutex> lock(t->mutex);
            if (row.generation == t->counters.generation && !t->assignment_pending) continue;
            if (t->assignment_pending && row.generation == t->pending.generation) continue;
            t->pending = row;
            t->assignment_pending = true;
          }
          t->cv.notify_all();
        }
      });
  bus_.subscribe<task_trigger_t>(channels::kTaskTrigger, [this](const task_trigger_t& msg) {
    if (!msg.process.empty() && msg.process != options_.process) return;
    Task* t = find(msg.task);
    if (t != nullptr && !t->periodic) trigger(msg.task);
  });
  bus_.start();

  for (auto& t : tasks_) {
    Task* task = t.get();
    task->thread = std::thread([this, task] { task_main(*task); });
  }
  housekeeping_ = std::thread([this] { housekeeping_main(); });
}

void TaskRuntime::stop() {
  if (!started_) return;
  {
    std::lock_guard<std::mutex> lock(stop_mutex_);
    if (stopping_) return;
    stopping_ = true;
  }
  stop_cv_.notify_all();
  for (auto& t : tasks_) {
    {
      std::lock_guard<std::mutex> lock(t->mutex);
      t->stop = true;
    }
    t->cv.notify_all();
  }
  for (auto& t : tasks_)
    if (t->thread.joinable()) t->thread.join();
  if (housekeeping_.joinable()) housekeeping_.join();
  for (auto& t : tasks_) publish_jobs(*t, false);
  // start() started the bus thread: stop it too, so no callback (which may
  // refer to this runtime or to the caller's locals) outlives the tasks.
  bus_.stop();
}

TaskCounters TaskRuntime::counters(const std::string& task) const {
  Task* t = find(task);
  if (t == nullptr) return {};
  std::lock_guard<std::mutex> lock(t->mutex);
  return t->counters;
}

// BEGIN_PROC's migrate step: apply the scheduler's newest row for this task.
void TaskRuntime::apply_pending(Task& task) {
  task_assignment_t row;
  {
    std::lock_guard<std::mutex> lock(task.mutex);
    if (!task.assignment_pending) return;
    row = task.pending;
    task.assignment_pending = false;
  }
  SchedRequest req;
  req.cpu = row.cpu;
  req.policy = row.policy == task_assignment_t::POLICY_FIFO ? Policy::kFifo : Policy::kOther;
  req.priority = row.priority;
  const SchedOutcome out = apply_to_calling_thread(req);

  if (!out.policy_ok && !g_warned_rt.exchange(true)) {
    spdlog::warn(
        "runtime: SCHED_FIFO refused for task {}/{}: {}. Running under SCHED_OTHER (rt=false); "
        "timing guarantees do not hold.",
        options_.process, task.name, out.error);
  }
  if (!out.affinity_ok && !g_warned_affinity.exchange(true)) {
    spdlog::warn("runtime: CPU affinity refused for task {}/{}: {}. Running on any CPU.",
                 options_.process, task.name, out.error);
  }
  std::lock_guard<std::mutex> lock(task.mutex);
  task.counters.generation = row.generation;
  task.policy = out.policy_ok ? row.policy : task_assignment_t::POLICY_OTHER;
  task.priority = out.policy_ok && req.policy == Policy::kFifo ? row.priority : 0;
  task.cpu = out.affinity_ok ? row.cpu : -1;
  task.counters.rt_granted = out.policy_ok && req.policy == Policy::kFifo;
  task.rt_error = out.error;
  task.state_changed = true;
  if (task.periodic && row.period_us > 0) task.period_ns = row.period_us * 1000;
  if (row.deadline_us > 0)
    task.deadline_ns = row.deadline_us * 1000;
  else if (task.periodic)
    task.deadline_ns = task.period_ns;
  spdlog::info(
      "runtime: task {} now cpu {} {} prio {} period {} us (generation {})", task.name, task.cpu,
      policy_name(task.policy == task_assignment_t::POLICY_FIFO ? Policy::kFifo : Policy::kOther),
      task.priority, to_us(task.period_ns), row.generation);
}

void TaskRuntime::task_main(Task& task) {
  task.tid = current_tid();
  publish_register(task);
  PeriodicRelease release(mono_ns(), task.periodic ? task.period_ns : 1);
  int64_t index = 0;
  int skipped = 0;
  while (true) {
    int64_t release_ns = 0;
    if (task.periodic) {
      sleep_until_mono_ns(release.next_release_ns());
      {
        std::lock_guard<std::mutex> lock(task.mutex);
        if (task.stop) return;
      }
      release_ns = release.next_release_ns();
    } else {
      std::unique_lock<std::mutex> lock(task.mutex);
      task.cv.wait(lock, [&] { return task.stop || task.triggered || task.assignment_pending; });
      if (task.stop) return;
      if (!task.triggered) {  // woken only to apply a new assignment
        lock.unlock();
        apply_pending(task);
        continue;
      }
      task.triggered = false;
      release_ns = task.trigger_release_ns;
    }

    apply_pending(task);  // BEGIN_PROC
    const int64_t start_ns = mono_ns();
    const int64_t start_cpu_ns = thread_cpu_ns();
    const int cpu = current_cpu();
    try {
      task.job();
    } catch (const std::exception& e) {
      spdlog::error("runtime: job of task {} threw: {}", task.name, e.what());
    }
    const int64_t end_ns = mono_ns();  // END_PROC
    const int64_t end_cpu_ns = thread_cpu_ns();

    task_job_t rec{};
    rec.utime = wall_us() - to_us(end_ns - release_ns);
    rec.index = index++;
    rec.release_mono_us = to_us(release_ns);
    rec.start_latency_us = static_cast<int32_t>(to_us(start_ns - release_ns));
    rec.exec_us = static_cast<int32_t>(to_us(end_ns - start_ns));
    rec.cpu_us = static_cast<int32_t>(to_us(end_cpu_ns - start_cpu_ns));
    int64_t deadline_ns = 0;
    int64_t period_ns = 0;
    int64_t anchor_ns = 0;
    {
      std::lock_guard<std::mutex> lock(task.mutex);
      deadline_ns = task.deadline_ns;
      period_ns = task.period_ns;
      anchor_ns = task.anchor_ns;
      task.anchor_ns = 0;
    }
    rec.deadline_met = end_ns <= release_ns + deadline_ns;
    rec.cpu = cpu;
    rec.skipped_releases = skipped;
    if (task.periodic) {
      if (period_ns != release.period_ns()) release.set_period(period_ns);
      if (anchor_ns > 0) {
        release.align(anchor_ns, mono_ns());
        skipped = 0;
      } else {
        skipped = release.advance(mono_ns());
      }
    }
    {
      std::lock_guard<std::mutex> lock(task.mutex);
      ++task.counters.jobs;
      if (!rec.deadline_met) ++task.counters.deadline_misses;
      task.counters.skipped_releases += skipped;
      if (task.batch.size() < 10000) task.batch.push_back(rec);
    }
  }
}

void TaskRuntime::publish_register(Task& task) {
  task_register_t msg{};
  msg.utime = wall_us();
  msg.host = options_.host;
  msg.process = options_.process;
  msg.task = task.name;
  msg.pid = getpid();
  msg.tid = task.tid;
  msg.periodic = task.periodic;
  {
    std::lock_guard<std::mutex> lock(task.mutex);
    msg.period_us = task.periodic ? to_us(task.period_ns) : 0;
    msg.deadline_us = to_us(task.deadline_ns);
  }
  bus_.publish(channels::kTaskRegister, msg);
}

void TaskRuntime::publish_jobs(Task& task, bool even_if_empty) {
  task_jobs_t msg{};
  {
    std::lock_guard<std::mutex> lock(task.mutex);
    // A batch without jobs still tells the scheduler how the task is
    // scheduled (a triggered task may not run for a long time).
    if (task.batch.empty() && !even_if_empty && !task.state_changed) return;
    task.state_changed = false;
    msg.jobs.swap(task.batch);
    msg.policy = task.policy;
    msg.priority = task.priority;
    msg.cpu = task.cpu;
    msg.generation = task.counters.generation;
    msg.rt_granted = task.counters.rt_granted;
    msg.rt_error = task.rt_error;
    msg.period_us = task.periodic ? to_us(task.period_ns) : 0;
    msg.deadline_us = to_us(task.deadline_ns);
  }
  msg.utime = wall_us();
  msg.host = options_.host;
  msg.process = options_.process;
  msg.task = task.name;
  msg.pid = getpid();
  msg.tid = task.tid;
  msg.num_jobs = static_cast<int32_t>(msg.jobs.size());
  bus_.publish(channels::kTaskJobs, msg);
}

void TaskRuntime::housekeeping_main() {
  int tick = 0;
  std::unique_lock<std::mutex> lock(stop_mutex_);
  while (!stop_cv_.wait_for(lock, std::chrono::milliseconds(100), [this] { return stopping_; })) {
    lock.unlock();
    const bool each_second = ++tick % 10 == 0;
    for (auto& t : tasks_) publish_jobs(*t, each_second);
    if (each_second)
      for (auto& t : tasks_) publish_register(*t);
    lock.lock();
  }
}

}  // namespace ephor
