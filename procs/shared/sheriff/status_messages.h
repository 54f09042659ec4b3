#pragma once
// ephor-sheriff's DEPUTY_STATUS handling, as main.cc runs it (out of main.cc,
// so that the fuzz target status_messages_fuzz.cc runs what the process
// runs): the bus thread keeps each status with its receive wall time
// (receive()), the main loop hands them to the Sheriff (drain()) every 20 ms,
// and prints the table again when table_signature() changes.

#include <cstdint>
#include <deque>
#include <mutex>
#include <string>
#include <utility>

#include "ephor/deputy_status_t.hpp"
#include "procs/shared/sheriff/sheriff.h"

namespace ephor::sheriff {

class StatusInbox {
 public:
  // The bus thread's handler: `received_wall_us` is this machine's wall
  // clock at receipt (the host's clock offset is measured from it).
  void receive(const deputy_status_t& status, int64_t received_wall_us);

  // Gives every status received since the last call to `sheriff`, in order,
  // as received at `now_ns` (monotonic). True when there was one.
  bool drain(Sheriff& sheriff, int64_t now_ns);

 private:
  std::mutex mutex_;
  std::deque<std::pair<deputy_status_t, int64_t>> statuses_;  // with receive wall time, us
};

// What changes the table in a way worth printing again (not CPU or uptime).
std::string table_signature(const Sheriff& sheriff, int64_t now_ns);

}  // namespace ephor::sheriff
