#pragma once
// ProcessUsage: CPU and resident memory of processes from /proc (Linux), for
// the deputy's status. CPU is the process's own user+system time (not its
// children's) over the interval since the previous sample of that pid.

#include <sys/types.h>

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace ephor::deputy {

struct UsageSample {
  float cpu_percent = 0.0f;  // % of one CPU since the previous sample; 0 on the first
  int64_t rss_bytes = 0;     // resident set size, bytes
};

class ProcessUsage {
 public:
  // Samples `pid` at CLOCK_MONOTONIC `now_ns`. nullopt when the process is
  // gone or /proc cannot be read.
  std::optional<UsageSample> sample(pid_t pid, int64_t now_ns);
  // Drops the history of pids not in `alive`.
  void forget_others(const std::vector<pid_t>& alive);

 private:
  struct Previous {
    int64_t cpu_ticks = 0;
    int64_t at_ns = 0;
  };
  std::map<pid_t, Previous> previous_;
};

// Fields 14 and 15 (utime + stime, clock ticks) of a /proc/PID/stat line;
// nullopt when the line is malformed. The command name (field 2) may hold
// spaces and parentheses, so parsing starts after its last ')'.
std::optional<int64_t> parse_stat_cpu_ticks(const std::string& stat_line);

// Processes whose environment holds NAME=VALUE (read from
// /proc/PID/environ, readable for our own processes) and whose parent's
// command name is not `live_parent_comm`: processes a dead deputy left
// behind. Our own pid is never listed.
std::vector<pid_t> find_leftovers(const std::string& env_name, const std::string& env_value,
                                  const std::string& live_parent_comm);

// Command name (/proc/PID/comm) of `pid`; "" when gone.
std::string process_comm(pid_t pid);

}  // namespace ephor::deputy
