#pragma once
// A host's EPHOR_SCHED_STATUS as the task table's plain structs (SchedTable):
// DisplayServer's conversion of the message, out of display_server.cc so the
// fuzz target display_server_fuzz.cc runs it on any message.

#include "common/display/sched_table.h"
#include "ephor/sched_status_t.hpp"

namespace ephor::display {

HostSched host_sched_of(const sched_status_t& m);

}  // namespace ephor::display
