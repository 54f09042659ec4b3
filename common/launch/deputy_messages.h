#pragma once
// Between the deputy's messages (deputy_orders_t in, deputy_status_t out) and
// its ProcessTable. No LCM here: the thin main in procs/shared/deputy/main.cc sends
// and receives.

#include <sys/types.h>

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "common/launch/process_table.h"
#include "common/launch/process_usage.h"
#include "ephor/deputy_orders_t.hpp"
#include "ephor/deputy_status_t.hpp"

namespace ephor::deputy {

// Name of the row that runs the host's ephor-scheduler.
inline constexpr const char* kSchedulerRow = "scheduler";
// Environment variable that marks every process a deputy starts with
// deputy_tag(): a new deputy finds what a dead one left behind by it.
inline constexpr const char* kDeputyTagVariable = "EPHOR_DEPUTY";

struct DeputySettings {
  std::string host;           // this deputy's host name
  std::string bin_dir;        // where ephor binaries are (EPHOR_BIN_DIR of the children)
  std::string lcm_url;        // the deputy's own URL, for children when the orders name none
  std::string manifest_path;  // where the deputy keeps its copy of the orders' manifest
};

// "HOST@URL": one deputy per host and LCM system.
std::string deputy_tag(const DeputySettings& settings);

// The process orders of `orders` for this deputy, the host's scheduler first
// when asked for, each with the environment ephor processes expect
// (EPHOR_PROCESS, EPHOR_HOST, EPHOR_MANIFEST, EPHOR_BIN_DIR, LCM_DEFAULT_URL,
// EPHOR_LAUNCHED, and the deputy tag). Throws std::invalid_argument naming the
// problem when the orders are malformed (wrong host, counts that disagree, a
// process without name or exec, a duplicate name, a process named
// "scheduler" while the deputy runs the scheduler).
std::vector<ProcessOrder> host_orders(const deputy_orders_t& orders,
                                      const DeputySettings& settings);

// The deputy's full status. `usage` maps pids to their newest sample.
deputy_status_t make_status(const ProcessTable& table, const std::map<pid_t, UsageSample>& usage,
                            const DeputySettings& settings, int64_t orders_utime,
                            const std::string& sheriff, int64_t now_ns);

}  // namespace ephor::deputy
