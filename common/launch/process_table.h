#pragma once
// ProcessTable: a deputy's process table as a pure state machine (no fork, no
// signals, no clock of its own). The sheriff's orders say what should run
// (desired state); the executor reports what happened (started, exited); the
// table answers with what to do next (start NAME, signal PID) and keeps the
// actual state, the restart count and the reason of the last change.
//
// Rules (libbot2 procman's, with a backoff):
// - orders are full state and idempotent: applying the same orders twice
//   changes nothing; a process missing from the orders is stopped and then
//   forgotten;
// - a crash (any exit but status 0 of an allow_exit process) restarts the
//   process after first_delay, doubling per crash in a row up to max_delay;
//   after max_restarts crashes in a row it is "failed" and stays down until
//   the orders ask for a new run (new run_id or command) or stop and start it;
//   a run that lasted stable_time resets the count;
// - stop = SIGTERM, then SIGKILL after stop_grace;
// - a new run_id, or a changed command line, restarts a running process.
//
// Times are CLOCK_MONOTONIC nanoseconds passed in by the caller, so tests
// drive the clock.

#include <sys/types.h>

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace ephor::deputy {

// What the orders ask of one process.
struct ProcessOrder {
  std::string name;
  std::string exec;                                      // name in the bin dir / $PATH, or a path
  std::vector<std::string> args;                         // argv[1..]
  std::vector<std::pair<std::string, std::string>> env;  // added to the deputy's environment
  bool run = true;                                       // false = keep it stopped
  int32_t run_id = -1;  // a value other than the current run's restarts it; -1 = any run will do
  bool allow_exit = false;  // exit status 0 is not a crash

  // Same command line, environment and exit rule (run and run_id aside).
  bool same_command(const ProcessOrder& other) const;
};

enum class ProcessState {
  kStopped,   // not running, and not waiting to be restarted
  kStarting,  // a start action was handed out; started() / start_failed() follows
  kRunning,
  kStopping,  // SIGTERM sent; SIGKILL at kill_at_ns
  kBackoff,   // crashed; restarted at next_start_ns
  kFailed,    // restart limit reached, or could not be started
  kFinished,  // exited with status 0 and allow_exit
};
const char* to_string(ProcessState state);

struct RestartPolicy {
  int64_t first_delay_ns = 100'000'000;     // wait after the first crash in a row
  int64_t max_delay_ns = 10'000'000'000;    // cap of the doubling wait
  int max_restarts = 10;                    // crashes in a row restarted before giving up
  int64_t stable_time_ns = 10'000'000'000;  // a run this long forgets earlier crashes
  int64_t stop_grace_ns = 3'000'000'000;    // SIGTERM to SIGKILL
};

struct ProcessRow {
  ProcessOrder order;       // newest orders for this process
  ProcessOrder started_as;  // the order of the current (or last) run
  ProcessState state = ProcessState::kStopped;
  pid_t pid = 0;        // 0 when not running
  int32_t run_id = -1;  // run_id of the current (or last) run; -1 = never started
  int restarts = 0;     // automatic restarts after crashes
  int crashes_in_row = 0;
  int exit_code = -1;          // last exit status; -1 = none yet or killed by a signal
  int exit_signal = 0;         // signal that ended the last run; 0 = none
  std::string reason;          // why the process is in its state, for people
  int64_t started_ns = 0;      // start of the current run
  int64_t next_start_ns = 0;   // kBackoff: when to restart
  int64_t kill_at_ns = 0;      // kStopping: when to send SIGKILL
  bool kill_sent = false;      // kStopping: SIGKILL already sent
  bool forget = false;         // no longer in the orders: drop the row once stopped
  bool crash_restart = false;  // kStarting: restarted after a crash (reason keeps the crash)
  std::string last_crash;      // how the last crashed run ended, e.g. "killed by signal 9 (Killed)"
};

struct Action {
  enum class Kind { kStart, kSignal };
  Kind kind = Kind::kStart;
  std::string name;  // the process
  pid_t pid = 0;     // kSignal: whom
  int signal = 0;    // kSignal: SIGTERM or SIGKILL
};

class ProcessTable {
 public:
  explicit ProcessTable(RestartPolicy policy = {});

  // Replaces the desired state with `orders` (every process this deputy
  // should know). Rows keep the orders' sequence: processes start in it.
  // Throws std::invalid_argument when two orders share a name.
  void apply(const std::vector<ProcessOrder>& orders, int64_t now_ns);

  // The executor started the process that a kStart action named.
  void started(const std::string& name, pid_t pid, int64_t now_ns);
  // The executor could not start it (e.g. no such executable): kFailed.
  void start_failed(const std::string& name, const std::string& reason);
  // A child exited. `description` says how, e.g. "killed by signal 9 (Killed)".
  // Unknown pids are ignored.
  void exited(pid_t pid, bool signaled, int code, const std::string& description, int64_t now_ns);

  // What to do now. Call after every event and at next_deadline_ns().
  std::vector<Action> step(int64_t now_ns);

  // Earliest time at which step() has timed work (a restart, a SIGKILL);
  // INT64_MAX when none.
  int64_t next_deadline_ns() const;

  const std::vector<ProcessRow>& rows() const { return rows_; }
  const ProcessRow* find(const std::string& name) const;
  // Grows on every change of a row's state, pid or reason (publish status then).
  uint64_t version() const { return version_; }

 private:
  ProcessRow* find_mutable(const std::string& name);
  ProcessRow* find_by_pid(pid_t pid);
  static bool wants_new_run(const ProcessRow& row);
  void set_state(ProcessRow& row, ProcessState state, std::string reason);
  void begin_stop(ProcessRow& row, int64_t now_ns, std::vector<Action>& actions,
                  const std::string& reason);

  RestartPolicy policy_;
  std::vector<ProcessRow> rows_;
  uint64_t version_ = 0;
};

}  // namespace ephor::deputy
