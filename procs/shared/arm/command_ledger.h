#pragma once
// CommandLedger: the arm's memory of the commands it has answered, so that
// each command is executed at most once (paper section 3.3: the
// communication process retransmits until it hears back). A command is
// identified by its seq and the wall time it was first sent (arm_cmd_t.utime,
// the same in every retransmission), so a restarted sender whose seq starts
// again from 1 is not mistaken for a repeat.
//
// Keeps the newest `capacity` commands; not thread safe (one owner).

#include <cstddef>
#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <utility>

#include "procs/shared/arm/arm_command.h"

namespace ephor::arm {

class CommandLedger {
 public:
  explicit CommandLedger(std::size_t capacity = 4096) : capacity_(capacity) {}

  // The newest ack sent for this command, if it was seen before.
  std::optional<ArmAck> find(int64_t seq, int64_t first_sent_utime) const;
  // Records (or updates) the newest ack of a command.
  void record(int64_t seq, int64_t first_sent_utime, const ArmAck& ack);

  std::size_t size() const { return acks_.size(); }

 private:
  using Key = std::pair<int64_t, int64_t>;
  std::size_t capacity_;
  std::map<Key, ArmAck> acks_;
  std::deque<Key> order_;  // insertion order, for eviction
};

}  // namespace ephor::arm
