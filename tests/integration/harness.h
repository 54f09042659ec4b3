#pragma once
// Helpers for multi-process integration tests: start real ephor processes,
// watch their output, listen on LCM, and wait on conditions with timeouts
// (never on bare sleeps).

#include <chrono>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "common/launch/process_group.h"

namespace ephor::testing {

// Polls `pred` until it is true or `timeout` passes; returns its last value.
bool wait_until(const std::function<bool()>& pred, std::chrono::milliseconds timeout);

// Path of an ephor binary (from EPHOR_BIN_DIR, set by CTest).
std::string bin(const std::string& name);
// Path of a file in the source tree (from EPHOR_SOURCE_DIR, set by CTest).
std::string source_path(const std::string& relative);

// Writes `text` to a new file in a private temporary directory; returns its path.
std::string write_temp_file(const std::string& name, const std::string& text);

// Messages of one channel in a recorded LCM log: how many, the longest time
// between two consecutive ones (s) and when it began (s after the log's first
// event of any channel).
struct ChannelGap {
  int count = 0;
  double longest_s = 0.0;
  double at_s = 0.0;
};
ChannelGap longest_gap_in_log(const std::string& log_path, const std::string& channel);

class Processes;
// The pid ephor-launch (started as `launcher`) last reported for one of its
// processes ("started NAME (pid N)"): a restart gives a new one. 0 if none.
int launched_pid(const Processes& p, const std::string& launcher, const std::string& process);

// kill -9 of `process` (one of the launcher's), then waits until the launcher
// has started it again (a new pid). Seconds from the kill to the new pid; a
// negative value when it had no pid (-1) or was not restarted within
// `timeout` (-2).
double kill_and_await_restart(const Processes& p, const std::string& launcher,
                              const std::string& process, std::chrono::milliseconds timeout);

// Messages heard per channel on one LCM URL from construction on (counted,
// not decoded: any type). For "the system's outputs flow again".
class ChannelCounter {
 public:
  ChannelCounter(const std::string& url, const std::vector<std::string>& channels);
  ~ChannelCounter();
  ChannelCounter(const ChannelCounter&) = delete;
  ChannelCounter& operator=(const ChannelCounter&) = delete;
  int64_t count(const std::string& channel) const;
  // True once every channel of `at_least` has had that many messages.
  bool reached(const std::map<std::string, int64_t>& at_least) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Issue 18's fault run: each of `victims` (processes of the launcher started
// as `launcher`) killed with SIGKILL in turn; after each, waits for the
// launcher to restart it and for every channel of `resume` to carry that
// many new messages, and prints a line. A process not restarted, or outputs
// not flowing again, within the timeouts is a test failure (gtest) and ends
// the run of kills. Returns the seconds from each kill to the new pid, for
// the processes that came back.
std::map<std::string, double> kill_each_in_turn(
    const Processes& p, const std::string& launcher, const std::vector<std::string>& victims,
    const ChannelCounter& heard, const std::map<std::string, int64_t>& resume,
    std::chrono::milliseconds restart_timeout = std::chrono::seconds(5),
    std::chrono::milliseconds flowing_timeout = std::chrono::seconds(15));

// While it lives, every packet arriving on lo is dropped with probability
// `probability` (iptables' statistic match: the kernel here has no
// sch_netem). Only for a test in its own network namespace (NETNS).
class PacketLoss {
 public:
  explicit PacketLoss(double probability);  // throws when iptables refuses
  ~PacketLoss();
  PacketLoss(const PacketLoss&) = delete;
  PacketLoss& operator=(const PacketLoss&) = delete;

 private:
  std::string rule_;
};

// How many times the arm set off on each goal id, from the arm's lines in the
// launcher's output ("[arm ...] seq 14 goal 14: cartesian move to ..."): a
// fault test's "no goal runs twice". Every start counts, a restarted arm's
// too: a restarted arm refuses the command the killed one was executing
// (procs/shared/arm CommandLedger), so it never sets off on it again.
std::map<std::string, int> arm_goal_starts(const std::vector<std::string>& launcher_lines);

// The fault tests' shared checks (gtest EXPECTs; each prints what it saw).
//
// The process started as `name` (the launcher) has exited with status 0: no
// process of the run failed. `what` says where (e.g. "under packet loss").
void expect_clean_exit(const Processes& p, const std::string& name, const std::string& what = "");
// The arm set off on every goal at most once (arm_goal_starts over the
// launcher's lines, restarts included) and on at least `at_least` goals. Returns how many goals it
// set off on.
size_t expect_each_goal_once(const Processes& p, const std::string& launcher, size_t at_least);
// The slowest of kill_each_in_turn's restarts (s); 0 when none.
double slowest_restart_s(const std::map<std::string, double>& restart_s_of);
// Each channel of `bounds` (channel, seconds) in the recorded log has at
// least `min_messages` messages and no gap as long as its bound.
void expect_log_gaps_within(const std::string& log_path,
                            const std::vector<std::pair<std::string, double>>& bounds,
                            int min_messages);

// Child processes with their output kept for assertions. Stops them all on
// destruction.
class Processes {
 public:
  Processes();
  ~Processes();
  // Starts `exec` (a path) as `name`; env entries are added to ours.
  void start(const std::string& name, const std::string& exec, const std::vector<std::string>& args,
             const std::vector<std::pair<std::string, std::string>>& env = {});
  std::vector<std::string> lines(const std::string& name) const;
  // True when some line of `name` contains `text`.
  bool has_line(const std::string& name, const std::string& text) const;
  // Exits observed so far.
  std::vector<launcher::ExitInfo> exits() const;
  // True once the process started as `name` has exited.
  bool exited(const std::string& name) const;
  // Sends `sig` to the process started as `name`.
  void signal(const std::string& name, int sig);
  void stop_all();

 private:
  mutable std::mutex mutex_;
  std::unique_ptr<launcher::ProcessGroup> group_;
  std::map<std::string, std::vector<std::string>> lines_;
  std::vector<launcher::ExitInfo> exits_;
  std::map<std::string, int> pids_;
  bool running_ = true;
  std::thread poller_;
};

}  // namespace ephor::testing
