// Fuzz target (issue 18): ephor-sheriff's DEPUTY_STATUS handler on any
// stream of status messages, interleaved with the main loop's rounds and
// the commands typed on stdin, as main.cc runs them: each status decoded as
// the bus does (a message that does not decode to its full size is
// dropped) and received by StatusInbox with the fake wall clock; each round
// drains the inbox into the Sheriff (the first round ends the listening:
// adopt()), then the orders sent, host_events(), the table and its
// table_signature(), converged() with what it waits for. The manifest is
// fixed (two hosts, four processes, one gui, one allowed to exit); the
// statuses name its hosts or others, its processes or others.
//
// Checked after every round: a round drains exactly the statuses received
// since the last; the hosts are the manifest's, in its order; every manifest
// process has one row, an extra row only on a manifest host and only while
// its deputy reports it, no (host, name) twice; a host keeps at most its 10
// newest clock offsets and shows their minimum; the orders are one a host
// (in one-shot mode one a heard host), the manifest's processes in order,
// run ids -1 or more, and encode; the table has its header, one line per
// process row and the lines its hosts' state adds (clock offset, no deputy
// or lost), and neither it nor the events or what converged() waits for
// holds a control character other than the newline (they go to a
// terminal); a command on a manifest process or "all" is taken (unless a
// new run is asked for past the last run id), any other refused with a
// message.
//
// Input: a FuzzMessageStream (common/fuzz/fuzz_input.h) of up to 256
// messages of up to 4096 bytes; channels 0 DEPUTY_STATUS (deputy_status_t),
// 1 a main loop round (the first round's first byte, bit 0: one-shot mode,
// a command given on the command line: adopt(false) and orders of heard hosts
// only), 2 a command (byte 0 mod 3: start, stop, restart; byte 1 the
// target: a manifest process, "all", or the rest of the bytes as a name).
// The clocks advance by each record's step. Seeds: fuzz_corpus/sheriff_status
// (two deputies reporting everything running, a crash and restart through a
// command; a host that goes silent and comes back; extras and a foreign
// host) and the inputs of the faults it found (crash-*: a process name with
// a newline, a name longer than a table line, a restart past run id
// 2^31 - 1).
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "common/config/manifest.h"
#include "common/fuzz/fuzz_input.h"
#include "ephor/deputy_orders_t.hpp"
#include "ephor/deputy_status_t.hpp"
#include "procs/shared/sheriff/sheriff.h"
#include "procs/shared/sheriff/status_messages.h"

namespace {

using namespace ephor;
using namespace ephor::sheriff;

constexpr const char* kManifest = R"pb(
  name: "fuzz"
  host { name: "planning" }
  host { name: "arm" }
  param { name: "period" default_value: "10" }
  process {
    name: "vision"
    host: "planning"
    exec: "ephor-testtask"
    args: [ "--task", "periodic:v:${period}" ]
  }
  process { name: "display" host: "planning" exec: "ephor-display" gui: true }
  process { name: "arm" host: "arm" exec: "ephor-arm" }
  process { name: "calibrate" host: "arm" exec: "ephor-calibrate" allow_exit: true }
)pb";

const config::Manifest& manifest() {
  static const config::Manifest m = parse_manifest(kManifest, "fuzz.pbtxt");
  return m;
}

void single_lines(const std::string& text, const char* what) {
  for (char c : text)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f)
      fuzz::fail(std::string(what) + " with a control character: " + text);
}

void check_table(const Sheriff& sheriff, int64_t now_ns, const SheriffOptions& options) {
  const std::string table = sheriff.table(now_ns);
  size_t expected = 1;
  for (const HostView& h : sheriff.hosts()) {
    size_t rows = 0;
    for (const ProcessView& p : sheriff.processes()) rows += p.host == h.name ? 1 : 0;
    if (rows == 0) continue;
    const bool alive = h.last_status_ns >= 0 && now_ns - h.last_status_ns < options.lost_after_ns;
    expected += rows + (alive && h.offset_plus_delay_us != 0 ? 1 : 0) + (alive ? 0 : 1);
  }
  const size_t lines = static_cast<size_t>(std::count(table.begin(), table.end(), '\n'));
  if (lines != expected || table.empty() || table.back() != '\n')
    fuzz::fail("a table of " + std::to_string(lines) + " lines, not " + std::to_string(expected) +
               ":\n" + table);
  for (char c : table)
    if (c != '\n' && (static_cast<unsigned char>(c) < 0x20 || c == 0x7f))
      fuzz::fail("a table with a control character:\n" + table);
}

void check_views(const Sheriff& sheriff) {
  const std::vector<std::string> hosts = manifest_hosts(manifest());
  if (sheriff.hosts().size() != hosts.size()) fuzz::fail("hosts added or lost");
  for (size_t i = 0; i < hosts.size(); ++i) {
    const HostView& h = sheriff.hosts()[i];
    if (h.name != hosts[i]) fuzz::fail("host " + h.name + " where the manifest has " + hosts[i]);
    if (h.recent_offsets_us.size() > 10) fuzz::fail("more than 10 clock offsets kept");
    if (!h.recent_offsets_us.empty() &&
        h.offset_plus_delay_us !=
            *std::min_element(h.recent_offsets_us.begin(), h.recent_offsets_us.end()))
      fuzz::fail("a clock offset that is not the minimum of the recent ones");
  }
  std::set<std::pair<std::string, std::string>> seen;
  for (const ProcessView& p : sheriff.processes()) {
    if (!seen.insert({p.host, p.name}).second) fuzz::fail("two rows for " + p.name + "@" + p.host);
    if (std::find(hosts.begin(), hosts.end(), p.host) == hosts.end())
      fuzz::fail("a row on host " + p.host + ", which the manifest does not name");
    if (p.desired_run_id < -1) fuzz::fail("run id " + std::to_string(p.desired_run_id));
    if (!p.in_manifest && p.name != "scheduler" && !p.reported)
      fuzz::fail("extra " + p.name + " kept after its deputy stopped reporting it");
  }
  for (const auto& m : manifest().process()) {
    const ProcessView* v = sheriff.find(m.host(), m.name());
    if (v == nullptr || !v->in_manifest) fuzz::fail("manifest process " + m.name() + " lost");
  }
}

void check_orders(const Sheriff& sheriff, bool one_shot) {
  const std::vector<deputy_orders_t> orders = sheriff.orders(one_shot);
  size_t expected = 0;
  for (const HostView& h : sheriff.hosts()) expected += !one_shot || h.last_status_ns >= 0 ? 1 : 0;
  if (orders.size() != expected) fuzz::fail("orders for the wrong number of hosts");
  for (const deputy_orders_t& o : orders) {
    size_t n = 0;
    for (const auto& m : manifest().process()) {
      if (m.host() != o.host) continue;
      if (n >= o.processes.size() || o.processes[n].name != m.name())
        fuzz::fail("orders for " + o.host + " without " + m.name() + " in its place");
      if (o.processes[n].run_id < -1) fuzz::fail("orders with run id below -1");
      ++n;
    }
    if (n != o.processes.size() || o.num_processes != static_cast<int32_t>(n))
      fuzz::fail("orders for " + o.host + " with processes the manifest does not have");
    const int size = o.getEncodedSize();
    std::vector<uint8_t> bytes(static_cast<size_t>(size));
    if (o.encode(bytes.data(), 0, size) != size) fuzz::fail("orders that do not encode");
  }
}

void run_command(Sheriff& sheriff, const fuzz::FuzzMessage& msg) {
  if (msg.size < 2) return;
  const Command command = msg.bytes[0] % 3 == 0   ? Command::kStart
                          : msg.bytes[0] % 3 == 1 ? Command::kStop
                                                  : Command::kRestart;
  const int n = manifest().process_size();
  const int pick = msg.bytes[1] % (n + 2);
  const std::string target = pick < n    ? manifest().process(pick).name()
                             : pick == n ? std::string("all")
                                         : std::string(reinterpret_cast<const char*>(msg.bytes + 2),
                                                       static_cast<size_t>(msg.size - 2));
  bool known = target == "all";
  for (const auto& m : manifest().process()) known = known || m.name() == target;
  try {
    sheriff.command(command, target);
    if (!known) fuzz::fail("a command on unknown process '" + target + "' taken");
  } catch (const std::invalid_argument& e) {
    if (std::string(e.what()).empty()) fuzz::fail("a command refused without a reason");
    if (known && std::string(e.what()).find("the last there is") == std::string::npos)
      fuzz::fail(std::string("a command on a manifest process refused: ") + e.what());
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  SheriffOptions options;
  options.params = manifest_params(manifest(), {});
  options.lcm_url = "udpm://239.255.76.67:7667?ttl=0";
  options.id = "sheriff@fuzz:1";
  Sheriff sheriff(manifest(), options);
  StatusInbox inbox;
  int64_t mono_ns = 1'000'000'000;
  int64_t wall_us = 1'700'000'000'000'000;
  bool listening = true;
  bool one_shot = false;
  int received = 0;
  fuzz::FuzzMessageStream stream(data, size, 3);
  fuzz::FuzzMessage msg;
  while (stream.next(msg)) {
    mono_ns += msg.step_us * 1000;
    wall_us += msg.step_us;
    if (msg.channel == 0) {
      deputy_status_t s;
      if (!msg.decode(s)) continue;  // the bus counts a decode error
      inbox.receive(s, wall_us);
      ++received;
      continue;
    }
    if (msg.channel == 2) {
      if (!listening) run_command(sheriff, msg);
      continue;
    }
    if (inbox.drain(sheriff, mono_ns) != (received > 0)) fuzz::fail("drained the wrong statuses");
    received = 0;
    if (listening) {
      listening = false;
      one_shot = msg.size > 0 && (msg.bytes[0] & 1) != 0;
      sheriff.adopt(!one_shot);
    }
    check_views(sheriff);
    check_orders(sheriff, one_shot);
    for (const std::string& e : sheriff.host_events(mono_ns)) single_lines(e, "a host event");
    check_table(sheriff, mono_ns, options);
    (void)table_signature(sheriff, mono_ns);
    std::vector<std::string> waiting;
    const bool converged = sheriff.converged(mono_ns, &waiting);
    if (converged != waiting.empty()) fuzz::fail("converged while waiting for something");
    for (const std::string& w : waiting) single_lines(w, "what the sheriff waits for");
  }
  return 0;
}
