// Fuzz target (issue 18): a stream of EPHOR_DEPUTY_ORDERS messages as
// ephor-deputy takes them: each decoded as deputy_orders_t the way the bus
// does (a message that does not decode to its full size is dropped), other
// hosts' orders skipped, host_orders() (wrong host, counts that disagree, a
// process without name or exec, duplicate names, the scheduler's row), the
// process table's apply() (as DeputyCore::apply) and step(), whose actions
// are carried out by a stand-in for the process group (no process is
// started: a start gets a made-up pid or fails, a signal ends the process, a
// running process may crash), and the status the deputy publishes
// (make_status(), encoded). Bad orders must throw std::invalid_argument (the
// deputy logs and ignores them); the table's rows must keep unique names and
// a pid only while a process runs.
//
// Input: up to 32 messages, each a 2-byte little-endian length and that many
// bytes, then one byte for the stand-in: bit 0 a start fails, bit 1 a
// running process crashes (the byte after each message).
// Seeds: fuzz_corpus/deputy_orders (orders of a two-process host with the
// scheduler, then the same with one process stopped and one restarted).
#include <csignal>
#include <cstddef>
#include <cstdint>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/fuzz/fuzz_input.h"
#include "common/launch/deputy_messages.h"
#include "common/launch/process_table.h"
#include "ephor/deputy_orders_t.hpp"
#include "ephor/deputy_status_t.hpp"

namespace {

using namespace ephor;
using namespace ephor::deputy;

constexpr int64_t kStepNs = 500'000'000;  // between messages: the sheriff's orders come at 1-2 Hz

// What DeputyCore and its ProcessGroup would do with the table's actions.
void carry_out(ProcessTable& table, int64_t now_ns, uint8_t how, pid_t& next_pid) {
  for (int round = 0; round < 4; ++round) {
    const std::vector<Action> actions = table.step(now_ns);
    if (actions.empty()) return;
    for (const Action& a : actions) {
      if (a.kind == Action::Kind::kStart) {
        if ((how & 1) != 0)
          table.start_failed(a.name, "no such executable (fuzz)");
        else
          table.started(a.name, ++next_pid, now_ns);
      } else {
        table.exited(a.pid, true, 0, "killed by signal " + std::to_string(a.signal), now_ns);
      }
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  DeputySettings settings;
  settings.host = "lab1";
  settings.bin_dir = "/nonexistent/bin";
  settings.lcm_url = "udpm://239.255.76.67:7667?ttl=0";
  settings.manifest_path = "/nonexistent/manifest.pbtxt";
  RestartPolicy policy;
  policy.max_restarts = 3;
  ProcessTable table(policy);
  pid_t next_pid = 1000;
  int64_t now_ns = 1'000'000'000;
  int64_t orders_utime = 0;
  std::string sheriff;
  size_t at = 0;
  for (int k = 0; k < 32 && at + 2 <= size; ++k) {
    const size_t len = data[at] | (static_cast<size_t>(data[at + 1]) << 8);
    at += 2;
    if (len > size - at) break;
    deputy_orders_t o;
    const int n = static_cast<int>(len);
    const bool whole = o.decode(data + at, 0, n) == n;
    at += len;
    const uint8_t how = at < size ? data[at++] : 0;
    now_ns += kStepNs;
    if (whole && o.host == settings.host) {
      try {
        table.apply(host_orders(o, settings), now_ns);
        orders_utime = o.utime;
        sheriff = o.sheriff;
      } catch (const std::invalid_argument& e) {
        if (std::string(e.what()).empty()) fuzz::fail("bad orders refused without a reason");
      }
    }
    carry_out(table, now_ns, how, next_pid);
    if ((how & 2) != 0) {
      for (const ProcessRow& r : table.rows()) {
        if (r.pid == 0) continue;
        table.exited(r.pid, true, 0, "killed by signal 9 (Killed)", now_ns);
        break;
      }
      carry_out(table, now_ns, how, next_pid);
    }
    std::set<std::string> names;
    for (const ProcessRow& r : table.rows()) {
      if (!names.insert(r.order.name).second) fuzz::fail("two rows for process " + r.order.name);
      const bool alive = r.state == ProcessState::kRunning || r.state == ProcessState::kStopping;
      if ((r.pid != 0) != alive)
        fuzz::fail("process " + r.order.name + " in state " + to_string(r.state) + " with pid " +
                   std::to_string(r.pid));
    }
    deputy_status_t s = make_status(table, {}, settings, orders_utime, sheriff, now_ns);
    const int bytes = s.getEncodedSize();
    std::vector<uint8_t> out(static_cast<size_t>(bytes));
    if (s.encode(out.data(), 0, bytes) != bytes) fuzz::fail("the status does not encode");
  }
  return 0;
}
