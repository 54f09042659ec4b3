// ephor-scheduler with real task processes, in a private network namespace.
// Checks with the kernel (sched_getaffinity / sched_getscheduler on the task
// threads) that assignments really take effect.

#include <map>
#include <mutex>

#include <gtest/gtest.h>

#include "common/lcm/bus.h"
#include "common/runtime/channels.h"
#include "common/runtime/thread_sched.h"
#include "ephor/sched_status_t.hpp"
#include "ephor/task_jobs_t.hpp"
#include "ephor/task_register_t.hpp"
#include "ephor/task_trigger_t.hpp"
#include "tests/integration/harness.h"

namespace ephor::testing {
namespace {

using std::chrono::seconds;

// Listens to the runtime's channels and keeps what the tests ask about.
class RuntimeProbe {
 public:
  RuntimeProbe() : bus_("", "probe") {
    bus_.subscribe<task_register_t>(channels::kTaskRegister, [this](const task_register_t& m) {
      std::lock_guard<std::mutex> lock(mutex_);
      tids_[m.process + "/" + m.task] = m.tid;
    });
    bus_.subscribe<task_jobs_t>(channels::kTaskJobs, [this](const task_jobs_t& m) {
      std::lock_guard<std::mutex> lock(mutex_);
      jobs_[m.process + "/" + m.task] += m.num_jobs;
    });
    bus_.subscribe<sched_status_t>(channels::kSchedStatus, [this](const sched_status_t& m) {
      std::lock_guard<std::mutex> lock(mutex_);
      status_ = m;
      ++statuses_;
    });
    bus_.start();
  }
  int tid(const std::string& key) {
    std::lock_guard<std::mutex> lock(mutex_);
    return tids_.count(key) ? tids_[key] : 0;
  }
  int64_t jobs(const std::string& key) {
    std::lock_guard<std::mutex> lock(mutex_);
    return jobs_[key];
  }
  std::optional<task_status_t> status_of(const std::string& key) {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& t : status_.tasks)
      if (t.process + "/" + t.task == key) return t;
    return std::nullopt;
  }
  sched_status_t status() {
    std::lock_guard<std::mutex> lock(mutex_);
    return status_;
  }
  Bus& bus() { return bus_; }

 private:
  Bus bus_;
  std::mutex mutex_;
  std::map<std::string, int> tids_;
  std::map<std::string, int64_t> jobs_;
  sched_status_t status_{};
  int statuses_ = 0;
};

// True when thread `tid` runs with the given CPU and policy (kernel's view).
bool thread_has(int tid, int cpu, Policy policy) {
  if (tid <= 0) return false;
  const SchedReadback rb = read_thread_sched(tid);
  return rb.ok && rb.cpu == cpu && rb.policy == policy;
}

std::vector<std::pair<std::string, std::string>> env_for(const std::string& process) {
  return {{"EPHOR_PROCESS", process}, {"EPHOR_HOST", "testhost"}};
}

class SchedulerIntegration : public ::testing::Test {
 protected:
  void start_scheduler(const std::string& manifest_text) {
    const std::string path = write_temp_file(
        ::testing::UnitTest::GetInstance()->current_test_info()->name() + std::string(".pbtxt"),
        manifest_text);
    procs.start("scheduler", bin("ephor-scheduler"), {"--manifest", path, "--print-every", "0"},
                env_for("scheduler"));
  }
  void start_tasks(const std::string& process, const std::vector<std::string>& specs,
                   const std::string& wrapper = "") {
    std::vector<std::string> args;
    for (const auto& s : specs) {
      args.push_back("--task");
      args.push_back(s);
    }
    if (wrapper.empty()) {
      procs.start(process, bin("ephor-testtask"), args, env_for(process));
    } else {
      // Run under a wrapper script (e.g. one that drops CAP_SYS_NICE).
      args.insert(args.begin(), bin("ephor-testtask"));
      args.insert(args.begin(), {"-c", wrapper + " \"$@\"", "wrapper"});
      procs.start(process, "/bin/sh", args, env_for(process));
    }
  }
  RuntimeProbe probe;
  Processes procs;
};

constexpr const char* kTwoProcesses = R"pb(
  name: "itest"
  scheduler { status_period_s: 0.5 }
  host { name: "testhost" }
  process {
    name: "alpha"
    exec: "ephor-testtask"
    task { name: "fast" kind: PERIODIC period_ms: 2 cpu: "1" }
    task { name: "slow" kind: PERIODIC period_ms: 50 cpu: "0" priority: 20 }
  }
  process {
    name: "beta"
    exec: "ephor-testtask"
    task { name: "save" kind: TRIGGERED deadline_ms: 100 cpu: "0" }
    task { name: "log" kind: PERIODIC period_ms: 100 policy: OTHER cpu: "1" }
  }
)pb";

TEST_F(SchedulerIntegration, EachTaskRunsOnItsAssignedCpuAndPolicy) {
  ASSERT_GE(online_cpus(), 2) << "this test needs two CPUs";
  start_scheduler(kTwoProcesses);
  start_tasks("alpha", {"periodic:fast:2:100", "periodic:slow:50:500"});
  start_tasks("beta", {"triggered:save:100", "periodic:log:100:10"});

  EXPECT_TRUE(wait_until([&] { return thread_has(probe.tid("alpha/fast"), 1, Policy::kFifo); },
                         seconds(10)));
  EXPECT_TRUE(wait_until([&] { return thread_has(probe.tid("alpha/slow"), 0, Policy::kFifo); },
                         seconds(10)));
  EXPECT_TRUE(wait_until([&] { return thread_has(probe.tid("beta/save"), 0, Policy::kFifo); },
                         seconds(10)));
  EXPECT_TRUE(wait_until([&] { return thread_has(probe.tid("beta/log"), 1, Policy::kOther); },
                         seconds(10)));
  // Rate-monotonic priority for the 2 ms task (highest), explicit 20 for "slow".
  EXPECT_EQ(read_thread_sched(probe.tid("alpha/fast")).priority, 80);
  EXPECT_EQ(read_thread_sched(probe.tid("alpha/slow")).priority, 20);

  // The scheduler's status agrees and says real-time scheduling was granted.
  EXPECT_TRUE(wait_until(
      [&] {
        auto s = probe.status_of("alpha/fast");
        return s && s->alive && s->rt_granted && s->cpu == 1 && s->policy == "SCHED_FIFO" &&
               s->jobs > 100;
      },
      seconds(10)));
  EXPECT_TRUE(wait_until([&] { return probe.status().rt; }, seconds(5)));
  auto fast = probe.status_of("alpha/fast");
  ASSERT_TRUE(fast.has_value());
  EXPECT_EQ(fast->period_us, 2000);
  EXPECT_GT(fast->exec_p50_us, 50.0f);  // the task burns 100 us per job
  EXPECT_LT(fast->exec_p50_us, 2000.0f);
}

TEST_F(SchedulerIntegration, TriggeredTaskRunsOncePerTrigger) {
  start_scheduler(kTwoProcesses);
  start_tasks("beta", {"triggered:save:100", "periodic:log:100:10"});
  ASSERT_TRUE(wait_until([&] { return probe.tid("beta/save") > 0; }, seconds(10)));
  for (int i = 1; i <= 5; ++i) {
    task_trigger_t t{};
    t.utime = wall_us();
    t.process = "beta";
    t.task = "save";
    probe.bus().publish(channels::kTaskTrigger, t);
    // One job per trigger: wait for it before sending the next.
    ASSERT_TRUE(wait_until([&] { return probe.jobs("beta/save") == i; }, seconds(5)))
        << "trigger " << i;
  }
  // A trigger for another process's task is not ours.
  task_trigger_t other{};
  other.process = "alpha";
  other.task = "save";
  probe.bus().publish(channels::kTaskTrigger, other);
  // The periodic task keeps running meanwhile; after 3 more of its batches no
  // extra job of "save" has appeared.
  const int64_t log_jobs = probe.jobs("beta/log");
  ASSERT_TRUE(wait_until([&] { return probe.jobs("beta/log") >= log_jobs + 3; }, seconds(5)));
  EXPECT_EQ(probe.jobs("beta/save"), 5);
}

TEST_F(SchedulerIntegration, OverloadedCpuMigratesATaskAtRunTime) {
  ASSERT_GE(online_cpus(), 2) << "this test needs two CPUs";
  // Both "auto" tasks start on CPU 0 (no estimates given); together they
  // need 2 x 4.5 ms every 10 ms = 0.9 of CPU 0, over the bound for two tasks
  // (0.83). SCHED_OTHER so the overload cannot starve the machine.
  start_scheduler(R"pb(
    name: "migrate"
    scheduler { status_period_s: 0.5 }
    host { name: "testhost" }
    process {
      name: "gamma"
      exec: "ephor-testtask"
      task { name: "a" kind: PERIODIC period_ms: 10 policy: OTHER }
      task { name: "b" kind: PERIODIC period_ms: 10 policy: OTHER }
    }
  )pb");
  start_tasks("gamma", {"periodic:a:10:4500", "periodic:b:10:4500"});
  ASSERT_TRUE(wait_until(
      [&] {
        return thread_has(probe.tid("gamma/a"), 0, Policy::kOther) &&
               thread_has(probe.tid("gamma/b"), 0, Policy::kOther);
      },
      seconds(10)));
  // The scheduler notices the overload and moves one of them to CPU 1.
  EXPECT_TRUE(wait_until(
      [&] {
        return thread_has(probe.tid("gamma/a"), 1, Policy::kOther) ||
               thread_has(probe.tid("gamma/b"), 1, Policy::kOther);
      },
      seconds(15)));
  EXPECT_TRUE(
      wait_until([&] { return procs.has_line("scheduler", "migrating gamma/"); }, seconds(5)));
  EXPECT_TRUE(wait_until(
      [&] {
        for (const auto& e : probe.status().events)
          if (e.find("migrating gamma/") != std::string::npos) return true;
        return false;
      },
      seconds(5)));
}

TEST_F(SchedulerIntegration, RefusedFifoFallsBackWithWarningAndRtFalse) {
  start_scheduler(kTwoProcesses);
  // Drop CAP_SYS_NICE and set RLIMIT_RTPRIO to 0: sched_setscheduler(SCHED_FIFO)
  // now fails with EPERM, as for an unprivileged user or in a container.
  start_tasks("alpha", {"periodic:fast:2:100", "periodic:slow:50:500"},
              "exec setpriv --inh-caps=-sys_nice --bounding-set=-sys_nice prlimit --rtprio=0 --");
  EXPECT_TRUE(
      wait_until([&] { return procs.has_line("alpha", "SCHED_FIFO refused"); }, seconds(10)));
  EXPECT_TRUE(wait_until([&] { return thread_has(probe.tid("alpha/fast"), 1, Policy::kOther); },
                         seconds(10)));
  // The process keeps running its jobs under SCHED_OTHER...
  EXPECT_TRUE(wait_until([&] { return probe.jobs("alpha/fast") > 200; }, seconds(10)));
  // ...warns once, and the scheduler reports rt=false.
  int warnings = 0;
  for (const auto& l : procs.lines("alpha"))
    warnings += l.find("SCHED_FIFO refused") != std::string::npos;
  EXPECT_EQ(warnings, 1);
  EXPECT_TRUE(wait_until(
      [&] {
        auto s = probe.status_of("alpha/fast");
        return s && s->alive && !s->rt_granted && s->policy == "SCHED_OTHER" && !probe.status().rt;
      },
      seconds(10)));
  EXPECT_TRUE(wait_until([&] { return procs.has_line("scheduler", "SCHED_FIFO was refused"); },
                         seconds(5)));
  for (const auto& e : procs.exits()) ADD_FAILURE() << e.name << " " << e.describe();
}

}  // namespace
}  // namespace ephor::testing
