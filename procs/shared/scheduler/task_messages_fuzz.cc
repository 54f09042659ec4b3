// Fuzz target (issue 18): a stream of the task messages ephor-scheduler
// takes, EPHOR_TASK_REGISTER (task_register_t) and EPHOR_TASK_JOBS
// (task_jobs_t), each decoded the way the bus does (a message that does not
// decode to its full size is dropped), converted by registration_of() /
// jobs_report_of() (other hosts' skipped) and given to the Scheduler as
// main.cc does (on_register / on_jobs), with its status cycle between them
// as the main loop runs it: rebalance(), the new refusals, status(),
// assignments(). Messages with any numbers: negative or huge pids, periods,
// deadlines, job times, unknown tasks, a task's pid changing (a restart). The
// kernel readback is a stand-in (no thread of the fuzzer is looked at). Every
// utilisation and bound must be a number, every assignment's CPU one the
// scheduler has or -1.
//
// Input: up to 64 messages, each a byte (bit 0: task_jobs_t, else
// task_register_t; bit 1: the status cycle runs after it), a 2-byte
// little-endian length and that many bytes. 100 ms pass per message.
// Seeds: fuzz_corpus/scheduler_tasks (deploy/sched_demo.pbtxt's tasks
// registering and reporting jobs, one restarting, one overloading a CPU).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "common/config/manifest.h"
#include "common/fuzz/fuzz_input.h"
#include "ephor/task_jobs_t.hpp"
#include "ephor/task_register_t.hpp"
#include "procs/shared/scheduler/scheduler.h"
#include "procs/shared/scheduler/task_messages.h"
#include "procs/shared/scheduler/task_table.h"

namespace {

using namespace ephor;
using namespace ephor::scheduler;

// deploy/sched_demo.pbtxt's processes, on host "local".
constexpr const char* kManifest = R"pb(
  name: "sched_demo"
  lcm { port: 7667 ttl: 0 }
  scheduler { status_period_s: 1 }
  host { name: "local" }
  process {
    name: "sensor"
    exec: "ephor-testtask"
    task { name: "sample" kind: PERIODIC period_ms: 1 cpu: "1" }
    task { name: "filter" kind: PERIODIC period_ms: 10 cpu: "auto" expected_exec_ms: 1 }
  }
  process {
    name: "actuator"
    exec: "ephor-testtask"
    task { name: "move" kind: TRIGGERED deadline_ms: 20 cpu: "0" }
    task { name: "report" kind: PERIODIC period_ms: 100 policy: OTHER }
  }
)pb";

void check(const Scheduler& sched, const std::vector<int>& cpus, int64_t now_us) {
  const HostStatus hs = sched.status(now_us);
  for (size_t i = 0; i < hs.cpu_utilisation.size(); ++i)
    if (std::isnan(hs.cpu_utilisation[i]) || std::isnan(hs.cpu_bound[i]))
      fuzz::fail("a CPU's utilisation or bound is NaN");
  for (const TaskStatus& t : hs.tasks)
    if (std::isnan(t.utilisation) || std::isnan(t.exec_p99) || std::isnan(t.jitter_p99))
      fuzz::fail("task " + t.assignment.process + "/" + t.assignment.task + ": NaN figures");
  for (const Assignment& a : sched.assignments()) {
    bool known = a.cpu == -1;
    for (int c : cpus) known = known || c == a.cpu;
    if (!known) fuzz::fail("task " + a.process + "/" + a.task + " assigned to an unknown CPU");
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const config::Manifest manifest = parse_manifest(kManifest, "sched_demo (fuzz)");
  const std::string host = "local";
  SchedulerConfig cfg;
  cfg.cpus = {0, 1};
  cfg.history = 64;
  // The kernel's answer for any thread: as asked, so the fuzzer's own
  // threads are never read; tid 13 is a thread that has gone.
  Scheduler sched(cfg, build_task_table(manifest, host), [](pid_t tid) {
    SchedReadback r;
    r.ok = tid != 13;
    r.cpu = static_cast<int>(tid % 3) - 1;
    r.policy = tid % 2 == 0 ? Policy::kFifo : Policy::kOther;
    r.priority = r.policy == Policy::kFifo ? 50 : 0;
    return r;
  });
  int64_t now_us = 1'000'000;
  size_t at = 0;
  for (int k = 0; k < 64 && at + 3 <= size; ++k) {
    const uint8_t how = data[at];
    const size_t len = data[at + 1] | (static_cast<size_t>(data[at + 2]) << 8);
    at += 3;
    if (len > size - at) break;
    const int n = static_cast<int>(len);
    now_us += 100'000;
    if ((how & 1) != 0) {
      task_jobs_t m;
      if (m.decode(data + at, 0, n) == n)
        if (const auto r = jobs_report_of(m, host)) sched.on_jobs(*r, now_us);
    } else {
      task_register_t m;
      if (m.decode(data + at, 0, n) == n)
        if (const auto r = registration_of(m, host)) sched.on_register(*r, now_us);
    }
    at += len;
    if ((how & 2) != 0) {
      sched.rebalance(now_us);
      sched.take_new_refusals();
      check(sched, cfg.cpus, now_us);
    }
  }
  check(sched, cfg.cpus, now_us);
  return 0;
}
