// ephor-deputy: runs on each host and keeps the processes the sheriff's
// orders assign to this host in their desired state (libbot2 procman's
// deputy).
//
//   ephor-deputy --host NAME [--lcm-url URL] [--quiet]
//
// Listens to deputy_orders_t on EPHOR_DEPUTY_ORDERS (full desired state, for
// this host only); starts the host's ephor-scheduler first, then the ordered
// processes; restarts crashed ones with a doubling backoff and a limit; stops
// by SIGTERM then SIGKILL after a grace time; publishes their output on
// EPHOR_DEPUTY_OUTPUT (and prints it prefixed with the process name unless
// --quiet) and its full status on EPHOR_DEPUTY_STATUS at 4 Hz and on every
// change. Without orders it runs nothing; when the sheriff goes away it keeps
// the last orders. On SIGINT/SIGTERM it stops its processes and exits.
//
// Starting, restarting and stopping are DeputyCore's (procs/shared/deputy/
// deputy_core.h), the same as ephor-launch runs in-process; this file only
// turns orders into its desired state and its table into status messages.
//
// The processes it starts get the deputy's tag in their environment
// (EPHOR_DEPUTY=HOST@URL); at start a deputy stops processes with its tag that
// a previous deputy left behind (their parent died), so a restarted deputy
// never runs a process twice.

#include <signal.h>
#include <unistd.h>

#include <cstdio>
#include <deque>
#include <filesystem>
#include <fstream>
#include <map>

#include <CLI/CLI.hpp>

#include "common/launch/deputy_core.h"
#include "common/launch/deputy_messages.h"
#include "common/launch/process_usage.h"
#include "common/lcm/bus.h"
#include "common/runtime/channels.h"
#include "common/runtime/process_args.h"
#include "common/time/clock.h"
#include "ephor/deputy_output_t.hpp"

namespace {

using namespace ephor;
using namespace ephor::deputy;

// Status goes out at 4 Hz so that the sheriff's 2.5 s "deputy lost" needs
// nine status messages lost in a row: at 5 % packet loss two in a row (which
// a 1 Hz status cannot survive) happen every few minutes. CPU use is still
// measured over a whole second so its figure stays steady.
constexpr int64_t kStatusPeriodNs = 250'000'000;
constexpr int64_t kUsagePeriodNs = 1'000'000'000;
constexpr int64_t kOutputPeriodNs = 100'000'000;
constexpr size_t kMaxLinesPerMessage = 200;
constexpr size_t kMaxLineBytes = 2000;

std::string self_dir() {
  std::error_code ec;
  const auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::string() : exe.parent_path().string();
}

void say(const std::string& host, const std::string& text) {
  std::printf("[deputy@%s] %s\n", host.c_str(), text.c_str());
  std::fflush(stdout);
}

// Stops what a dead deputy of this host left behind: SIGTERM, then SIGKILL.
void stop_leftovers(const DeputySettings& settings, int64_t grace_ns) {
  auto left = find_leftovers(kDeputyTagVariable, deputy_tag(settings), "ephor-deputy");
  if (left.empty()) return;
  std::string names;
  for (pid_t p : left) names += " " + process_comm(p) + "(" + std::to_string(p) + ")";
  say(settings.host, "stopping " + std::to_string(left.size()) +
                         " process(es) a previous deputy left running:" + names);
  for (pid_t p : left) kill(p, SIGTERM);
  const int64_t deadline = mono_ns() + grace_ns;
  while (mono_ns() < deadline) {
    bool any = false;
    for (pid_t p : left) any = any || kill(p, 0) == 0;
    if (!any) return;
    usleep(20'000);
  }
  for (pid_t p : left) kill(p, SIGKILL);
}

// What happened to a process, for people. Signals the deputy sends are not
// printed: the exit that follows them is.
void report(const std::string& host, const DeputyEvent& e) {
  switch (e.kind) {
    case DeputyEvent::Kind::kStarted:
      say(host, "started " + e.name + " (pid " + std::to_string(e.pid) + ", run " +
                    std::to_string(e.run_id) + "): " + e.path);
      break;
    case DeputyEvent::Kind::kStartFailed:
      // ProcessGroup's reasons already say "cannot start NAME (PATH): ...".
      say(host, e.reason.rfind("cannot start ", 0) == 0
                    ? e.reason
                    : "cannot start " + e.name + ": " + e.reason);
      break;
    case DeputyEvent::Kind::kExited:
      say(host, e.name + " (pid " + std::to_string(e.pid) + ") " + e.exit.describe() +
                    (e.in_table ? std::string(": ") + to_string(e.state) : std::string()));
      break;
    case DeputyEvent::Kind::kSignalled:
      break;
  }
}

}  // namespace

int main(int argc, char** argv) {
  block_shutdown_signals();
  CLI::App app{"ephor-deputy: runs the processes the sheriff's orders assign to this host"};
  ProcessArgs args;
  add_process_flags(app, args, "deputy");
  bool quiet = false;
  double grace_s = 3.0;
  app.add_flag("--quiet", quiet, "do not print the processes' output (it is still published)");
  app.add_option("--grace", grace_s, "seconds between SIGTERM and SIGKILL when stopping a process")
      ->check(CLI::NonNegativeNumber);
  if (const auto exit_status = ephor::parse_flags(app, argc, argv)) return *exit_status;
  if (args.host.empty()) {
    std::fprintf(stderr, "ephor-deputy: --host must not be empty\n");
    return 2;
  }

  DeputySettings settings;
  settings.host = args.host;
  settings.lcm_url = resolve_lcm_url(args.lcm_url);
  settings.bin_dir =
      std::getenv("EPHOR_BIN_DIR") != nullptr ? std::getenv("EPHOR_BIN_DIR") : self_dir();
  const char* runtime_dir = std::getenv("XDG_RUNTIME_DIR");
  const std::filesystem::path state_dir =
      std::filesystem::path(runtime_dir != nullptr && *runtime_dir != '\0' ? runtime_dir : "/tmp") /
      ("ephor-deputy-" + args.host + "-" + std::to_string(getpid()));
  settings.manifest_path = (state_dir / "manifest.pbtxt").string();

  RestartPolicy policy;
  policy.stop_grace_ns = static_cast<int64_t>(grace_s * 1e9);
  ProcessUsage usage;
  std::map<pid_t, UsageSample> usage_now;

  try {
    std::filesystem::create_directories(state_dir);
    Bus bus(settings.lcm_url, "deputy@" + args.host);
    auto orders_box = std::make_shared<Mailbox<deputy_orders_t>>();
    const std::string host = args.host;
    bus.subscribe<deputy_orders_t>(channels::kDeputyOrders,
                                   [orders_box, host](const deputy_orders_t& o) {
                                     if (o.host == host) orders_box->put(o);
                                   });
    stop_leftovers(settings, policy.stop_grace_ns);
    bus.start();
    say(host,
        "ready on " + settings.lcm_url + "; waiting for orders on " + channels::kDeputyOrders);

    // Output lines of the children, published in batches.
    deputy_output_t output{};
    size_t dropped_lines = 0;
    DeputyCore core(
        policy, settings.bin_dir, [&](const std::string& name, const std::string& line) {
          if (!quiet) {
            std::printf("[%s] %s\n", name.c_str(), line.c_str());
            std::fflush(stdout);
          }
          if (output.lines.size() >= kMaxLinesPerMessage) {
            ++dropped_lines;
            return;
          }
          output.processes.push_back(name);
          output.lines.push_back(line.size() > kMaxLineBytes ? line.substr(0, kMaxLineBytes) + "..."
                                                             : line);
        });

    std::string manifest_text;
    int64_t orders_utime = 0;
    std::string sheriff;
    uint64_t published_version = ~uint64_t{0};
    int64_t next_status_ns = 0;
    int64_t next_usage_ns = 0;
    int64_t next_output_ns = 0;
    uint64_t bad_orders = 0;

    while (true) {
      if (const int sig = wait_for_shutdown_signal(0.001); sig != 0) {
        say(host, std::string("stopping on ") + (sig == SIGINT ? "SIGINT" : "SIGTERM"));
        break;
      }
      if (auto o = orders_box->take()) {
        try {
          const auto orders = host_orders(*o, settings);
          if (o->manifest_text != manifest_text) {
            std::ofstream(settings.manifest_path, std::ios::trunc) << o->manifest_text;
            manifest_text = o->manifest_text;
          }
          core.apply(orders);
          if (o->sheriff != sheriff) say(host, "orders from " + o->sheriff);
          orders_utime = o->utime;
          sheriff = o->sheriff;
        } catch (const std::exception& e) {
          if (bad_orders++ % 100 == 0) say(host, std::string("ignoring bad orders: ") + e.what());
        }
      }
      // The core wakes earlier for a restart or a SIGKILL that falls due.
      const int64_t until = next_output_ns - mono_ns();
      for (const auto& e :
           core.poll(static_cast<int>(std::clamp<int64_t>(until / 1'000'000, 0, 50))))
        report(host, e);
      const ProcessTable& table = core.table();
      const int64_t now = mono_ns();
      if (now >= next_output_ns) {
        next_output_ns = now + kOutputPeriodNs;
        if (dropped_lines > 0) {
          output.processes.push_back("deputy");
          output.lines.push_back(std::to_string(dropped_lines) + " output lines dropped");
          dropped_lines = 0;
        }
        if (!output.lines.empty()) {
          output.utime = wall_us();
          output.host = host;
          output.num_lines = static_cast<int32_t>(output.lines.size());
          bus.publish(channels::kDeputyOutput, output);
          output = deputy_output_t{};
        }
      }
      if (now >= next_status_ns || table.version() != published_version) {
        if (now >= next_usage_ns) {  // CPU over the whole usage period
          next_usage_ns = now + kUsagePeriodNs;
          std::vector<pid_t> alive;
          usage_now.clear();
          for (const auto& r : table.rows()) {
            if (r.pid == 0) continue;
            alive.push_back(r.pid);
            if (auto s = usage.sample(r.pid, now)) usage_now[r.pid] = *s;
          }
          usage.forget_others(alive);
        }
        if (now >= next_status_ns) next_status_ns = now + kStatusPeriodNs;
        auto status = make_status(table, usage_now, settings, orders_utime, sheriff, now);
        status.utime = wall_us();
        bus.publish(channels::kDeputyStatus, status);
        published_version = table.version();
      }
    }
    core.stop_all();
    bus.stop();
    std::error_code ec;
    std::filesystem::remove_all(state_dir, ec);
    say(host, "all stopped");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "[deputy@%s] %s\n", args.host.c_str(), e.what());
    return 1;
  }
  return 0;
}
