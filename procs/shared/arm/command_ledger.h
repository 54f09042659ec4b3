#pragma once
// CommandLedger: the arm's memory of the commands it has answered, so that
// each command is executed at most once (paper section 3.3: the
// communication process retransmits until it hears back). A command is
// identified by its seq and the wall time it was first sent (arm_cmd_t.utime,
// the same in every retransmission), so a restarted sender whose seq starts
// again from 1 is not mistaken for a repeat.
//
// The ledger lives as long as the arm process. A restarted arm has an empty
// one, and comm keeps polling the command the killed arm was executing (or
// retransmitting one the killed arm may have accepted unheard): the new
// ledger cannot tell whether such a command was executed. So the ledger
// knows when it began (`started_utime`, wall clock) and vouches only for
// commands first sent since then: every one of those that this run has not
// answered was never executed by any run (an arm run is dead before the next
// starts). A command first sent before that is refused (refusal()) and never
// executed: a restart costs at most that one goal, which comm reports FAILED
// and the planner sends again under a new id, never the same goal twice.
// This is procman's full-state rule applied to the arm: the arm reports what
// it holds (ARM_STATE executing_seq and last_done_seq are 0 after a restart)
// and acts only on what it can know, never on a guess about its past run.
// Clocks: comm stamps utime with its wall clock, the arm compares with its
// own; hosts whose clocks differ by more than an arm restart (~0.1-1 s)
// weaken the rule, as they already break the arm's max command age.
//
// Keeps the newest `capacity` commands; not thread safe (one owner).

#include <cstddef>
#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <string>
#include <utility>

#include "procs/shared/arm/arm_command.h"

namespace ephor::arm {

class CommandLedger {
 public:
  // `started_utime`: wall clock when this run of the arm began, us.
  explicit CommandLedger(int64_t started_utime, std::size_t capacity = 4096)
      : started_utime_(started_utime), capacity_(capacity) {}

  // The newest ack sent for this command, if it was seen before.
  std::optional<ArmAck> find(int64_t seq, int64_t first_sent_utime) const;
  // Why a command not found() must not be executed, or nullopt: it was first
  // sent before this ledger began, so an earlier run of the arm may have
  // executed it (see above). The arm answers FAILED with this reason.
  std::optional<std::string> refusal(int64_t seq, int64_t first_sent_utime) const;
  // Records (or updates) the newest ack of a command.
  void record(int64_t seq, int64_t first_sent_utime, const ArmAck& ack);

  int64_t started_utime() const { return started_utime_; }
  std::size_t size() const { return acks_.size(); }

 private:
  using Key = std::pair<int64_t, int64_t>;
  int64_t started_utime_;
  std::size_t capacity_;
  std::map<Key, ArmAck> acks_;
  std::deque<Key> order_;  // insertion order, for eviction
};

}  // namespace ephor::arm
