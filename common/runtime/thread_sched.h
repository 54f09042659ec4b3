#pragma once
// Applying and reading back a thread's CPU affinity and scheduling policy
// (sched_setaffinity / sched_setscheduler on Linux thread ids).

#include <sys/types.h>

#include <string>

namespace ephor {

enum class Policy { kOther = 0, kFifo = 1 };

struct SchedRequest {
  int cpu = -1;  // -1 = any CPU
  Policy policy = Policy::kOther;
  int priority = 0;  // SCHED_FIFO priority 1..99
};

struct SchedOutcome {
  bool affinity_ok = true;
  bool policy_ok = true;
  std::string error;  // why something was refused, "" when all applied
};

// Applies `req` to the calling thread. When SCHED_FIFO is refused (EPERM,
// RLIMIT_RTPRIO, a container) the thread is put under SCHED_OTHER instead and
// policy_ok is false; when the CPU is refused or does not exist the thread may
// run on any CPU and affinity_ok is false.
SchedOutcome apply_to_calling_thread(const SchedRequest& req);

struct SchedReadback {
  int cpu = -1;  // the single CPU the thread is pinned to, -1 when it may use several
  Policy policy = Policy::kOther;
  int priority = 0;
  bool ok = false;  // false when the thread does not exist (anymore)
};

// Reads back what thread `tid` (any process) is running with.
SchedReadback read_thread_sched(pid_t tid);

pid_t current_tid();
int current_cpu();
int online_cpus();
const char* policy_name(Policy p);

// Locks the process's memory (mlockall) so page faults do not add latency.
// Returns "" on success, else the reason it was refused.
std::string lock_process_memory();

}  // namespace ephor
