// ephor-launch: starts a deployment manifest on this machine.
//
//   ephor-launch deploy/shepherd.pbtxt [--duration S] [--host NAME] [--headless]
//                [--arg PROCESS=ARG ...] [--record FILE] [--restart] [--PARAM VALUE ...]
//
// --PARAM VALUE sets a parameter the manifest declares (param { name: ... }),
// e.g. --seed 7 --sheep 4 --summary out.json for deploy/shepherd.pbtxt.
//
// Starts one ephor-scheduler per host named by the selected processes (first),
// then every process of the manifest (or of --host only), prefixes their
// output with the process name, and stops all of them (SIGTERM, then SIGKILL
// after a grace time, newest first) on Ctrl-C, on SIGTERM or when --duration
// has passed. Exits non-zero, naming the process, when one cannot start or
// dies unexpectedly. With --restart a crashed process is restarted as a
// deputy does (doubling backoff from 0.1 s, at most 10 crashes in a row); the
// run ends with an error only when it gives up.
//
// One host and many hosts are the same code path: the processes run under
// the DeputyCore (common/launch/deputy_core.h) that ephor-deputy runs on each
// host of a multi-machine system, in-process here, one core for all hosts of
// the manifest, without LCM orders and with a restart policy of its own
// (max_restarts = 0 unless --restart).
//
// At the end of a run it prints each process's resident memory (after a
// warm-up, last, peak, growth per hour) and CPU time, sampled from /proc every
// --usage-period-s; --usage FILE writes the same as JSON (UsageLog). A soak:
// `--duration 3600 --usage usage.json`, then look at the growth column.
//
// --record FILE also runs Debian's lcm-logger (started first, so it is
// stopped last and logs the others' final messages) on the same LCM URL:
// every channel of the run goes to FILE (overwritten), for tools/ephor log.

#include <signal.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>

#include <CLI/CLI.hpp>

#include "common/config/manifest.h"
#include "common/config/text_proto.h"
#include "common/launch/deputy_core.h"
#include "common/launch/process_group.h"
#include "common/launch/process_usage.h"
#include "common/launch/usage_log.h"
#include "common/runtime/process_args.h"
#include "common/time/clock.h"

namespace {

using namespace ephor;
using namespace ephor::launcher;
using ephor::deputy::DeputyCore;
using ephor::deputy::DeputyEvent;
using ephor::deputy::ProcessOrder;
using ephor::deputy::ProcessState;

std::string self_dir() {
  std::error_code ec;
  const auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::string() : exe.parent_path().string();
}

std::string fmt_seconds(double s) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g s", s);
  return buf;
}

void say(const std::string& text) {
  std::printf("[launch] %s\n", text.c_str());
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  block_shutdown_signals();
  CLI::App app{"ephor-launch: run a deployment manifest on this machine"};
  std::string manifest_path;
  double duration_s = 0.0;
  std::string only_host;
  std::vector<std::string> extra_args;
  int grace_ms = 3000;
  bool no_scheduler = false;
  bool headless = false;
  std::string record_path;
  std::string record_channels;
  bool restart = false;
  std::string usage_path;
  double usage_period_s = 10.0;
  double usage_warmup_s = 60.0;
  app.add_option("manifest", manifest_path,
                 "deployment manifest (Protobuf text), e.g. deploy/shepherd.pbtxt")
      ->required();
  app.add_option("--duration", duration_s, "stop everything after S seconds (0 = until Ctrl-C)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--host", only_host,
                 "start only the processes of this host (default: all hosts, here)");
  app.add_option("--arg", extra_args,
                 "PROCESS=ARG: append ARG to PROCESS's command line (repeatable)");
  app.add_option("--grace-ms", grace_ms, "time between SIGTERM and SIGKILL when stopping")
      ->check(CLI::NonNegativeNumber);
  app.add_flag("--no-scheduler", no_scheduler,
               "do not start ephor-scheduler (tasks then run under SCHED_OTHER)");
  app.add_flag("--headless", headless, "do not start user-interface processes (gui: true)");
  auto* record_option = app.add_option(
      "--record", record_path, "record every LCM channel of the run to FILE with lcm-logger");
  app.add_option("--record-channels", record_channels,
                 "with --record: only channels matching this regular expression (lcm-logger -c), "
                 "e.g. 'BLOBS|OBJECTS|GROUND_TRUTH' for an hour's run without camera frames")
      ->needs(record_option);
  app.add_flag("--restart", restart,
               "restart crashed processes as a deputy does (backoff, at most 10 crashes in a row) "
               "instead of stopping everything");
  app.add_option("--usage", usage_path,
                 "write each process's memory and CPU over the run to FILE (JSON)");
  app.add_option("--usage-period-s", usage_period_s, "sample memory and CPU this often, s")
      ->check(CLI::Range(0.1, 3600.0));
  app.add_option("--usage-warmup-s", usage_warmup_s,
                 "memory growth is fitted to the samples after this much of each process's "
                 "run, s")
      ->check(CLI::NonNegativeNumber);
  app.allow_extras();
  app.footer("Any other --NAME VALUE sets a parameter the manifest declares.");
  if (const auto exit_status = ephor::parse_flags(app, argc, argv)) return *exit_status;

  config::Manifest manifest;
  try {
    manifest = load_manifest(manifest_path);
  } catch (const ConfigError& e) {
    std::fprintf(stderr, "[launch] bad manifest: %s\n", e.what());
    return 2;
  }

  // Manifest parameters: defaults, then --NAME VALUE / --NAME=VALUE.
  std::map<std::string, std::string> params;
  for (const auto& p : manifest.param()) params[p.name()] = p.default_value();
  const auto rest = app.remaining();
  for (size_t i = 0; i < rest.size(); ++i) {
    std::string name = rest[i];
    std::string value;
    if (name.rfind("--", 0) != 0) {
      std::fprintf(stderr, "[launch] unexpected argument '%s'\n", name.c_str());
      return 2;
    }
    name = name.substr(2);
    if (const auto eq = name.find('='); eq != std::string::npos) {
      value = name.substr(eq + 1);
      name = name.substr(0, eq);
    } else if (i + 1 < rest.size()) {
      value = rest[++i];
    }
    if (!params.count(name)) {
      std::string known;
      for (const auto& [k, _] : params) known += " --" + k;
      std::fprintf(stderr, "[launch] unknown option --%s (parameters of %s:%s)\n", name.c_str(),
                   manifest_path.c_str(), known.empty() ? " none" : known.c_str());
      return 2;
    }
    params[name] = value;
  }

  // Found out now, not at the end of an hour's run.
  if (!usage_path.empty() && !std::ofstream(usage_path)) {
    std::fprintf(stderr, "[launch] --usage: cannot write %s\n", usage_path.c_str());
    return 2;
  }

  std::map<std::string, std::vector<std::string>> more_args;
  for (const auto& a : extra_args) {
    const auto eq = a.find('=');
    bool known = false;
    for (const auto& p : manifest.process())
      known = known || (eq != std::string::npos && p.name() == a.substr(0, eq));
    if (!known) {
      std::fprintf(stderr, "[launch] --arg '%s': want PROCESS=ARG with a process of %s\n",
                   a.c_str(), manifest_path.c_str());
      return 2;
    }
    more_args[a.substr(0, eq)].push_back(a.substr(eq + 1));
  }
  if (!only_host.empty()) {
    const auto hosts = manifest_hosts(manifest);
    if (std::find(hosts.begin(), hosts.end(), only_host) == hosts.end()) {
      std::fprintf(stderr, "[launch] --host %s: not a host of %s\n", only_host.c_str(),
                   manifest_path.c_str());
      return 2;
    }
  }

  // The manifest's URL, unless the caller set one (tests, several systems).
  const char* env_url = std::getenv("LCM_DEFAULT_URL");
  const std::string url =
      env_url != nullptr && *env_url != '\0' ? env_url : manifest_lcm_url(manifest);
  const std::string bin_dir =
      std::getenv("EPHOR_BIN_DIR") != nullptr ? std::getenv("EPHOR_BIN_DIR") : self_dir();
  const std::string abs_manifest = std::filesystem::absolute(manifest_path).string();

  std::vector<ProcessOrder> orders;
  auto order = [](std::string name, std::string exec, std::vector<std::string> args,
                  std::vector<std::pair<std::string, std::string>> env, bool allow_exit) {
    ProcessOrder o;
    o.name = std::move(name);
    o.exec = std::move(exec);
    o.args = std::move(args);
    o.env = std::move(env);
    o.allow_exit = allow_exit;
    return o;
  };
  std::set<std::string> hosts;
  auto selected = [&](const config::Process& p) {
    return (only_host.empty() || p.host() == only_host) && !(headless && p.gui());
  };
  for (const auto& p : manifest.process())
    if (selected(p)) hosts.insert(p.host());
  auto base_env = [&](const std::string& name, const std::string& host) {
    return std::vector<std::pair<std::string, std::string>>{
        {"EPHOR_LAUNCHED", "1"},          {"EPHOR_PROCESS", name},    {"EPHOR_HOST", host},
        {"EPHOR_MANIFEST", abs_manifest}, {"EPHOR_BIN_DIR", bin_dir}, {"LCM_DEFAULT_URL", url}};
  };
  if (!record_path.empty()) {
    // lcm-logger 1.3.1 ignores -l: the URL goes in --lcm-url=. -q: errors
    // only, not a status line per second among the processes' output.
    const std::string logger = resolve_executable("lcm-logger", bin_dir);
    if (logger.empty()) {
      std::fprintf(stderr,
                   "[launch] --record: lcm-logger not found in $PATH (Debian package liblcm-bin; "
                   "run tools/ephor setup)\n");
      return 1;
    }
    const std::string abs_record = std::filesystem::absolute(record_path).string();
    // The largest receive buffer tools/ephor setup allows (net.core.rmem_max):
    // about 1.8 s of the catching camera's 18 MB/s while the disk stalls.
    const std::string logger_url = lcm_url_with_receive_buffer(url, 33554432);
    std::vector<std::string> logger_args{"--lcm-url=" + logger_url, "-q", "-f", abs_record};
    if (!record_channels.empty()) logger_args.push_back("--channel=" + record_channels);
    orders.push_back(order("logger", logger, logger_args,
                           base_env("logger", only_host.empty() ? "" : only_host), false));
  }
  if (!no_scheduler) {
    for (const auto& host : hosts) {
      const std::string name = hosts.size() == 1 ? "scheduler" : "scheduler@" + host;
      orders.push_back(order(name, "ephor-scheduler", {"--manifest", abs_manifest, "--host", host},
                             base_env(name, host), false));
    }
  }
  std::set<std::string> ends_run;  // processes whose finishing ends the run
  bool run_done = false;
  for (const auto& p : manifest.process()) {
    if (!selected(p)) continue;
    if (p.ends_run()) ends_run.insert(p.name());
    ProcessOrder o = order(p.name(), resolve_executable(p.exec(), bin_dir), expand_args(p, params),
                           base_env(p.name(), p.host()), p.allow_exit() || p.ends_run());
    for (const auto& a : more_args[p.name()]) o.args.push_back(a);
    // Checked before anything starts, with a hint: a missing binary is
    // usually a missing build, and nothing needs stopping yet.
    if (o.exec.empty()) {
      std::fprintf(stderr,
                   "[launch] cannot start %s: executable '%s' not found in %s or $PATH (built? "
                   "try: tools/ephor build)\n",
                   p.name().c_str(), p.exec().c_str(), bin_dir.c_str());
      return 1;
    }
    orders.push_back(std::move(o));
  }

  size_t width = 6;
  for (const auto& o : orders) width = std::max(width, o.name.size());
  deputy::RestartPolicy policy;
  if (!restart) policy.max_restarts = 0;  // a crash ends the run
  policy.stop_grace_ns = static_cast<int64_t>(grace_ms) * 1'000'000;
  DeputyCore core(policy, bin_dir, [width](const std::string& name, const std::string& line) {
    std::printf("[%-*s] %s\n", static_cast<int>(width), name.c_str(), line.c_str());
    std::fflush(stdout);
  });
  try {
    core.apply(orders);
  } catch (const std::invalid_argument& e) {  // e.g. a process named like a scheduler row
    std::fprintf(stderr, "[launch] %s: %s\n", manifest_path.c_str(), e.what());
    return 2;
  }

  // Reports an event; true when it ends the run.
  auto failed = [&](const DeputyEvent& e) {
    switch (e.kind) {
      case DeputyEvent::Kind::kStarted:
        say("started " + e.name + " (pid " + std::to_string(e.pid) + "): " + e.path);
        return false;
      case DeputyEvent::Kind::kStartFailed:
        // ProcessGroup's reasons already say "cannot start NAME (PATH): ...".
        std::fprintf(
            stderr, "[launch] %s\n",
            (e.reason.rfind("cannot start ", 0) == 0 ? e.reason
                                                     : "cannot start " + e.name + ": " + e.reason)
                .c_str());
        return true;
      case DeputyEvent::Kind::kExited:
        if (!e.in_table) return false;
        if (e.state == ProcessState::kFinished) {
          say(e.name + " finished");
          if (ends_run.count(e.name) != 0) run_done = true;
          return false;
        }
        if (e.state == ProcessState::kBackoff) {  // --restart
          const auto* row = core.table().find(e.name);
          say("process " + e.name + " crashed: " + e.exit.describe() + "; restart " +
              std::to_string(row->crashes_in_row) + " of " + std::to_string(policy.max_restarts) +
              " in " + fmt_seconds(static_cast<double>(row->next_start_ns - e.at_ns) / 1e9));
          return false;
        }
        if (e.state == ProcessState::kFailed) {
          const std::string gave_up =
              restart
                  ? " (gave up after " + std::to_string(core.table().find(e.name)->crashes_in_row) +
                        " crashes in a row)"
                  : "";
          std::fprintf(stderr, "[launch] process %s died unexpectedly: %s%s; stopping everything\n",
                       e.name.c_str(), e.exit.describe().c_str(), gave_up.c_str());
          return true;
        }
        return false;
      case DeputyEvent::Kind::kSignalled:
        return false;
    }
    return false;
  };

  say("manifest " + manifest.name() + ", LCM " + url);
  const int64_t t0_ns = mono_ns();
  launcher::UsageLog usage_log(usage_warmup_s);
  deputy::ProcessUsage usage;
  int64_t next_usage_ns = t0_ns;
  auto sample_usage = [&] {
    const int64_t now = mono_ns();
    std::vector<pid_t> alive;
    for (const auto& row : core.table().rows()) {
      if (row.pid == 0) continue;
      alive.push_back(row.pid);
      if (const auto u = usage.sample(row.pid, now))
        usage_log.add(row.order.name, static_cast<double>(now - t0_ns) / 1e9, u->cpu_percent,
                      u->rss_bytes);
    }
    usage.forget_others(alive);
  };
  int rc = 0;
  for (const auto& e : core.poll(0))  // starts everything, in the orders' sequence
    if (failed(e)) rc = 1;
  if (rc == 0) {
    say(duration_s > 0 ? "running for " + fmt_seconds(duration_s)
                       : "running; Ctrl-C stops everything");
    const int64_t end_ns =
        duration_s > 0 ? mono_ns() + static_cast<int64_t>(duration_s * 1e9) : INT64_MAX;
    while (true) {
      for (const auto& e : core.poll(100))
        if (failed(e)) rc = 1;
      if (rc != 0) break;
      if (run_done) {
        say("the run is over (a process that ends it finished); stopping");
        break;
      }
      if (mono_ns() >= next_usage_ns) {
        sample_usage();
        next_usage_ns += static_cast<int64_t>(usage_period_s * 1e9);
      }
      if (wait_for_shutdown_signal(0.001) != 0) {
        say("stopping on signal");
        break;
      }
      if (mono_ns() >= end_ns) {
        say("duration reached; stopping");
        break;
      }
    }
  }
  sample_usage();  // the processes as they end the run
  if (!usage_log.summaries().empty()) {
    say("memory and CPU over the run (rss after a " + fmt_seconds(usage_warmup_s) + " warm-up):");
    for (const auto& line : launcher::format_table(usage_log)) say("  " + line);
  }
  if (!usage_path.empty()) {
    std::ofstream out(usage_path);
    out << launcher::to_json(usage_log).dump(2) << "\n";
    if (!out) {
      std::fprintf(stderr, "[launch] --usage: cannot write %s\n", usage_path.c_str());
      if (rc == 0) rc = 1;
    }
  }
  for (const auto& e : core.stop_all()) {
    if (e.kind == DeputyEvent::Kind::kSignalled && e.signal == SIGKILL)
      say(e.name + " did not stop within the grace time: killed");
  }
  say(rc == 0 ? "all stopped" : "all stopped after a failure");
  return rc;
}
