#include "common/runtime/thread_sched.h"

#include <sched.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace ephor {

pid_t current_tid() { return static_cast<pid_t>(syscall(SYS_gettid)); }
int current_cpu() { return sched_getcpu(); }
int online_cpus() { return static_cast<int>(sysconf(_SC_NPROCESSORS_ONLN)); }
const char* policy_name(Policy p) { return p == Policy::kFifo ? "SCHED_FIFO" : "SCHED_OTHER"; }

SchedOutcome apply_to_calling_thread(const SchedRequest& req) {
  SchedOutcome out;
  cpu_set_t set;
  CPU_ZERO(&set);
  if (req.cpu >= 0 && req.cpu < CPU_SETSIZE) {
    CPU_SET(req.cpu, &set);
  } else {
    for (int c = 0; c < online_cpus(); ++c) CPU_SET(c, &set);
  }
  if (sched_setaffinity(0, sizeof set, &set) != 0) {
    out.affinity_ok = false;
    out.error = "sched_setaffinity(cpu " + std::to_string(req.cpu) + "): " + std::strerror(errno);
  }

  sched_param param{};
  if (req.policy == Policy::kFifo) {
    param.sched_priority = req.priority;
    if (sched_setscheduler(0, SCHED_FIFO, &param) != 0) {
      const int err = errno;
      rlimit rl{};
      getrlimit(RLIMIT_RTPRIO, &rl);
      out.policy_ok = false;
      if (!out.error.empty()) out.error += "; ";
      out.error +=
          "sched_setscheduler(SCHED_FIFO, " + std::to_string(req.priority) +
          "): " + std::strerror(err) + " (RLIMIT_RTPRIO " +
          (rl.rlim_cur == RLIM_INFINITY ? std::string("unlimited") : std::to_string(rl.rlim_cur)) +
          "; needs CAP_SYS_NICE or ulimit -r >= priority)";
      param.sched_priority = 0;
      sched_setscheduler(0, SCHED_OTHER, &param);
    }
  } else {
    param.sched_priority = 0;
    sched_setscheduler(0, SCHED_OTHER, &param);
  }
  return out;
}

SchedReadback read_thread_sched(pid_t tid) {
  SchedReadback rb;
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(tid, sizeof set, &set) != 0) return rb;
  if (CPU_COUNT(&set) == 1) {
    for (int c = 0; c < CPU_SETSIZE; ++c) {
      if (CPU_ISSET(c, &set)) {
        rb.cpu = c;
        break;
      }
    }
  }
  const int pol = sched_getscheduler(tid);
  if (pol < 0) return rb;
  rb.policy = (pol == SCHED_FIFO) ? Policy::kFifo : Policy::kOther;
  sched_param param{};
  if (sched_getparam(tid, &param) == 0) rb.priority = param.sched_priority;
  rb.ok = true;
  return rb;
}

std::string lock_process_memory() {
  if (mlockall(MCL_CURRENT | MCL_FUTURE) != 0)
    return std::string("mlockall: ") + std::strerror(errno);
  return "";
}

}  // namespace ephor
