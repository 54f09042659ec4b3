#pragma once
// Sheriff: the desired state of a whole deployment (every process of a
// manifest on its host) and the view of it rebuilt from the deputies' status
// messages (libbot2 procman's sheriff). No LCM here: procs/shared/sheriff/main.cc
// sends the orders and feeds in the status.
//
// Stateless protocol: orders() is the full desired state of each host, sent
// again and again; a deputy converges to it whatever it ran before. A sheriff
// that starts while the system runs first listens (on_status), then adopt()s
// what the deputies already run, so it restarts nothing.
//
// Times are CLOCK_MONOTONIC nanoseconds from the caller.

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "common/config/manifest.pb.h"
#include "ephor/deputy_orders_t.hpp"
#include "ephor/deputy_status_t.hpp"

namespace ephor::sheriff {

struct SheriffOptions {
  std::map<std::string, std::string> params;  // manifest parameter values (defaults filled)
  bool headless = false;                      // gui processes start stopped
  bool start_scheduler = true;                // deputies run each host's ephor-scheduler
  std::string lcm_url;                        // given to every process
  std::string id = "sheriff";                 // shown by deputies, e.g. "sheriff@lab1:4242"
  int64_t lost_after_ns = 2'500'000'000;      // no status for this long: host lost (4 Hz status)
};

enum class Command { kStart, kStop, kRestart };

// One process of the manifest (or reported by a deputy) as the sheriff sees it.
struct ProcessView {
  std::string host;
  std::string name;
  bool in_manifest = false;  // false: a deputy runs it but the manifest does not name it
  bool desired_run = false;
  int32_t desired_run_id = -1;                      // -1 = any run
  std::optional<deputy_process_status_t> reported;  // newest status row, if any
};

struct HostView {
  std::string name;
  int64_t last_status_ns = -1;  // -1 = never heard
  int32_t deputy_pid = 0;
  std::string orders_from;  // sheriff whose orders the deputy runs
  float load = 0.0f;        // 1-minute load average
  bool lost = false;        // reported lost (edge-triggered events)
  // Receive wall time minus the status's send time (deputy's clock), us:
  // the host's clock offset plus the one-way delay. Minimum over the newest
  // 10 status messages (the least delayed one); 0 when unknown.
  int64_t offset_plus_delay_us = 0;
  std::vector<int64_t> recent_offsets_us;
};

class Sheriff {
 public:
  // Throws std::invalid_argument when a manifest process is named
  // "scheduler" while deputies run the scheduler (the names would clash).
  Sheriff(config::Manifest manifest, SheriffOptions options);

  // A deputy's status, received at `now_ns` (monotonic) and, when known,
  // `receive_wall_us` (this machine's wall clock, for the clock offset).
  // Hosts the manifest does not name are ignored.
  void on_status(const deputy_status_t& status, int64_t now_ns, int64_t receive_wall_us = 0);

  // Sets the desired state from what the deputies report: a process a deputy
  // knows keeps its reported desired state and run; any other process gets
  // `default_run` (gui processes with headless: stopped).
  void adopt(bool default_run);

  // start / stop / restart one process or "all". start of a process that is
  // down for good (failed, finished) or restart asks the deputy for a new
  // run. Throws std::invalid_argument naming an unknown process.
  void command(Command command, const std::string& target);

  // The full orders of every host, in manifest order. With
  // `only_heard_hosts`, hosts whose deputy never reported are left out (a
  // one-shot command must not stop what it has not seen).
  std::vector<deputy_orders_t> orders(bool only_heard_hosts = false) const;

  // True when every manifest process (and each host's scheduler) is in its
  // desired state on a live deputy; otherwise false and `waiting_for` lists
  // what is not, e.g. "arm: backoff (crashed: killed by signal 9 (Killed))".
  bool converged(int64_t now_ns, std::vector<std::string>* waiting_for = nullptr) const;

  // Hosts whose deputy went silent or came back since the last call, as
  // messages for people ("host arm: deputy lost (no status for 2.6 s)").
  std::vector<std::string> host_events(int64_t now_ns);

  bool all_hosts_heard() const;
  const std::vector<HostView>& hosts() const { return hosts_; }
  const std::vector<ProcessView>& processes() const { return processes_; }
  const ProcessView* find(const std::string& host, const std::string& name) const;

  // The status table, one line per process, hosts in manifest order.
  std::string table(int64_t now_ns) const;

 private:
  ProcessView* find_mutable(const std::string& host, const std::string& name);
  HostView* find_host(const std::string& name);
  const HostView* find_host(const std::string& name) const;
  bool host_alive(const HostView& host, int64_t now_ns) const;

  config::Manifest manifest_;
  std::string manifest_text_;
  SheriffOptions options_;
  std::vector<HostView> hosts_;
  std::vector<ProcessView> processes_;  // manifest processes first, then reported extras
};

// Manifest parameters: defaults, then `overrides` ("--NAME VALUE" or
// "--NAME=VALUE" words). Throws std::invalid_argument naming an unknown
// parameter or a stray word.
std::map<std::string, std::string> manifest_params(const config::Manifest& manifest,
                                                   const std::vector<std::string>& overrides);

}  // namespace ephor::sheriff
