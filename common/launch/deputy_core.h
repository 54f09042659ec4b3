#pragma once
// DeputyCore: what a deputy does with its processes, without LCM. It joins
// the ProcessTable (the state machine: desired vs actual, backoff, limit) to
// a ProcessGroup (fork, output lines, reaping, signals): it hands the table's
// actions to the group (start NAME, signal PID) and the group's exits back to
// the table, and wakes for the table's timed work (a restart after its
// backoff, a SIGKILL after the grace time).
//
// Both ways of running a manifest go through it: ephor-deputy wraps one in
// LCM (orders in, status and output out) on every host, and ephor-launch
// (`tools/ephor run`) runs one in-process for the whole machine with a
// restart policy of its own (max_restarts = 0: a crash ends the run). So
// starting, restarting and stopping behave the same on one host and on many.
//
// Not thread-safe: one thread calls apply(), poll() and stop_all(); the line
// handler runs on that thread, inside poll() and stop_all().

#include <sys/types.h>

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "common/launch/process_group.h"
#include "common/launch/process_table.h"

namespace ephor::deputy {

// Something that happened to a process, for the wrapper to report.
struct DeputyEvent {
  enum class Kind {
    kStarted,      // forked and exec'd: pid, path
    kStartFailed,  // could not be started (no such executable, exec failed): reason; now failed
    kExited,       // a run ended: exit; state says what the table made of it
    kSignalled,    // sent `signal` to pid (a stop: SIGTERM, then SIGKILL after the grace time)
  };
  Kind kind = Kind::kStarted;
  std::string name;
  pid_t pid = 0;
  int64_t at_ns = 0;        // CLOCK_MONOTONIC time the table was told (or the signal sent)
  int32_t run_id = -1;      // kStarted: the run's id
  int signal = 0;           // kSignalled: SIGTERM or SIGKILL
  std::string path;         // kStarted: the executable
  launcher::ExitInfo exit;  // kExited: how the run ended
  // kExited: false when the process was no longer in the orders (its row is
  // gone once it stopped); state and reason are then meaningless.
  bool in_table = true;
  // The process's state after the event: kExited → kBackoff (restart
  // follows), kFailed (crashed once more than max_restarts allows),
  // kFinished (allowed exit), kStopped (it was being stopped); kStartFailed
  // → kFailed.
  ProcessState state = ProcessState::kStopped;
  std::string reason;  // the row's reason, e.g. "gave up after 1 crashes in a row; last ..."
};

class DeputyCore {
 public:
  // Executables of the orders are looked up in `bin_dir`, then in $PATH.
  // `on_line` gets every output line of every process (see ProcessGroup).
  DeputyCore(RestartPolicy policy, std::string bin_dir,
             launcher::ProcessGroup::LineHandler on_line);
  // Stops whatever still runs (stop_all()).
  ~DeputyCore();
  DeputyCore(const DeputyCore&) = delete;
  DeputyCore& operator=(const DeputyCore&) = delete;

  // Replaces the desired state (see ProcessTable::apply); the next poll()
  // acts on it at once. Throws std::invalid_argument when two orders share a
  // name.
  void apply(const std::vector<ProcessOrder>& orders);

  // Acts on what is due (starts in the orders' sequence, signals) and
  // returns at once when it did something. Otherwise waits up to
  // `timeout_ms` for output and exits (less when a restart or a SIGKILL
  // falls due earlier), hands the exits to the table and acts again. Returns
  // what happened, in order.
  std::vector<DeputyEvent> poll(int timeout_ms);

  // Stops every process and waits until all have exited: SIGTERM, newest
  // start first (the first started, e.g. a logger, is signalled last), and
  // SIGKILL to those still running after the policy's stop grace. The
  // desired state becomes "stopped": a later poll() starts nothing.
  std::vector<DeputyEvent> stop_all();

  // The state of every process (status, CPU sampling by pid).
  const ProcessTable& table() const { return table_; }

 private:
  void act(std::vector<DeputyEvent>& events);
  void send(const Action& action, std::vector<DeputyEvent>& events);
  void take_exits(const std::vector<launcher::ExitInfo>& exits, std::vector<DeputyEvent>& events);
  int wait_ms(int timeout_ms) const;

  RestartPolicy policy_;
  std::string bin_dir_;
  ProcessTable table_;
  launcher::ProcessGroup group_;
  std::map<pid_t, uint64_t> start_sequence_;  // pid -> how many starts came before it
  uint64_t starts_ = 0;
};

}  // namespace ephor::deputy
