// ephor-sheriff: sends every deputy its full orders from a deployment
// manifest and shows the status of the whole system (libbot2 procman's
// sheriff).
//
//   ephor-sheriff MANIFEST [--headless] [--PARAM VALUE ...]     live: start what is not
//                                                               running, show the table
//   ephor-sheriff MANIFEST --wait-running [--timeout S]         the same, exit 0 once all run
//   ephor-sheriff MANIFEST start|stop|restart NAME|all          change one process or all,
//                                                               exit 0 once done
//
// The sheriff first listens to the deputies' status (EPHOR_DEPUTY_STATUS) and
// adopts what they already run, so a sheriff that restarts restarts nothing.
// The live sheriff then sends orders (EPHOR_DEPUTY_ORDERS) at 1 Hz and on
// every change, prints the status table (redrawn every second on a terminal,
// printed on change otherwise), reports a host whose deputy goes silent
// within 3 s, and reads commands on stdin: start NAME, stop NAME, restart
// NAME (NAME or all). Leaving the sheriff leaves the system running: the
// deputies keep the last orders.

#include <poll.h>
#include <unistd.h>

#include <cstdio>
#include <sstream>

#include <CLI/CLI.hpp>

#include "common/config/manifest.h"
#include "common/config/text_proto.h"
#include "common/lcm/bus.h"
#include "common/runtime/channels.h"
#include "common/runtime/process_args.h"
#include "common/time/clock.h"
#include "procs/shared/sheriff/sheriff.h"
#include "procs/shared/sheriff/status_messages.h"

namespace {

using namespace ephor;
using namespace ephor::sheriff;

void say(const std::string& text) {
  std::printf("[sheriff] %s\n", text.c_str());
  std::fflush(stdout);
}

std::string hostname() {
  char buf[256] = {};
  return gethostname(buf, sizeof buf - 1) == 0 ? buf : "localhost";
}

std::optional<Command> parse_command(const std::string& word) {
  if (word == "start") return Command::kStart;
  if (word == "stop") return Command::kStop;
  if (word == "restart") return Command::kRestart;
  return std::nullopt;
}

// Complete lines typed on stdin so far (non-blocking); sets `eof` at its end.
std::vector<std::string> read_stdin_lines(std::string& partial, bool& eof) {
  std::vector<std::string> lines;
  pollfd fd{STDIN_FILENO, POLLIN, 0};
  while (!eof && ::poll(&fd, 1, 0) > 0) {
    char buf[512];
    const ssize_t n = read(STDIN_FILENO, buf, sizeof buf);
    if (n <= 0) {
      eof = true;
      break;
    }
    partial.append(buf, static_cast<size_t>(n));
  }
  size_t pos;
  while ((pos = partial.find('\n')) != std::string::npos) {
    lines.push_back(partial.substr(0, pos));
    partial.erase(0, pos + 1);
  }
  return lines;
}

}  // namespace

int main(int argc, char** argv) {
  block_shutdown_signals();
  CLI::App app{"ephor-sheriff: run a deployment manifest across hosts through their deputies"};
  std::string manifest_path;
  std::string command_word;
  std::string target;
  bool wait_running = false;
  bool headless = false;
  bool no_scheduler = false;
  double timeout_s = 30.0;
  double listen_s = 1.5;
  std::string lcm_url;
  app.add_option("manifest", manifest_path, "deployment manifest, e.g. deploy/shepherd.pbtxt")
      ->required();
  app.add_flag("--wait-running", wait_running,
               "exit 0 as soon as every process runs (1 after --timeout)");
  app.add_option("--timeout", timeout_s,
                 "seconds a command or --wait-running may take before exiting 1")
      ->check(CLI::PositiveNumber);
  app.add_option("--listen", listen_s,
                 "seconds to listen to the deputies before sending orders (status is 4 Hz)")
      ->check(CLI::NonNegativeNumber);
  app.add_flag("--headless", headless, "user-interface processes (gui: true) start stopped");
  app.add_flag("--no-scheduler", no_scheduler, "deputies do not run ephor-scheduler");
  app.add_option("--lcm-url", lcm_url,
                 "LCM URL (default: $LCM_DEFAULT_URL, else the manifest's lcm settings)");
  app.allow_extras();
  app.footer(
      "Then optionally a command: start|stop|restart NAME|all.\n"
      "Any other --NAME VALUE sets a parameter the manifest declares.");
  if (const auto exit_status = ephor::parse_flags(app, argc, argv)) return *exit_status;
  // The command words and the manifest's parameters come after CLI11's own
  // options: --NAME VALUE pairs are parameters, the other words the command.
  std::vector<std::string> param_words;
  std::vector<std::string> command_words;
  const auto rest = app.remaining();
  for (size_t i = 0; i < rest.size(); ++i) {
    if (rest[i].rfind("--", 0) == 0) {
      param_words.push_back(rest[i]);
      if (rest[i].find('=') == std::string::npos && i + 1 < rest.size())
        param_words.push_back(rest[++i]);
    } else {
      command_words.push_back(rest[i]);
    }
  }
  if (command_words.size() > 2) {
    std::fprintf(stderr, "[sheriff] unexpected argument '%s'\n", command_words[2].c_str());
    return 2;
  }
  if (!command_words.empty()) command_word = command_words[0];
  if (command_words.size() > 1) target = command_words[1];

  std::optional<Command> command;
  if (!command_word.empty()) {
    command = parse_command(command_word);
    if (!command || target.empty()) {
      std::fprintf(stderr, "[sheriff] want: %s MANIFEST start|stop|restart NAME|all\n", argv[0]);
      return 2;
    }
  }
  config::Manifest manifest;
  SheriffOptions options;
  try {
    manifest = load_manifest(manifest_path);
    options.params = manifest_params(manifest, param_words);
  } catch (const ConfigError& e) {
    std::fprintf(stderr, "[sheriff] bad manifest: %s\n", e.what());
    return 2;
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "[sheriff] %s\n", e.what());
    return 2;
  }
  const char* env_url = std::getenv("LCM_DEFAULT_URL");
  options.lcm_url = !lcm_url.empty()                         ? lcm_url
                    : env_url != nullptr && *env_url != '\0' ? std::string(env_url)
                                                             : manifest_lcm_url(manifest);
  options.headless = headless;
  options.start_scheduler = !no_scheduler;
  options.id = "sheriff@" + hostname() + ":" + std::to_string(getpid());

  try {
    Sheriff sheriff(manifest, options);
    Bus bus(options.lcm_url, "sheriff");
    StatusInbox inbox;
    bus.subscribe<deputy_status_t>(channels::kDeputyStatus,
                                   [&](const deputy_status_t& s) { inbox.receive(s, wall_us()); });
    bus.start();
    auto drain_status = [&] { return inbox.drain(sheriff, mono_ns()); };

    say("manifest " + manifest.name() + ", LCM " + options.lcm_url + "; listening to deputies");
    const int64_t listen_end = mono_ns() + static_cast<int64_t>(listen_s * 1e9);
    while (mono_ns() < listen_end && !sheriff.all_hosts_heard()) {
      drain_status();
      usleep(20'000);
    }
    drain_status();
    for (const auto& h : sheriff.hosts())
      if (h.last_status_ns < 0)
        say("host " + h.name + ": no deputy heard yet (run: ephor-deputy --host " + h.name + ")");
    sheriff.adopt(!command.has_value());
    if (command) {
      try {
        sheriff.command(*command, target);
      } catch (const std::invalid_argument& e) {
        std::fprintf(stderr, "[sheriff] %s\n", e.what());
        return 2;
      }
    }
    const bool one_shot = command.has_value() || wait_running;
    const bool interactive = isatty(STDOUT_FILENO) != 0;
    const int64_t start_ns = mono_ns();
    int64_t next_orders_ns = 0;
    int64_t next_table_ns = 0;
    std::string printed_signature;
    std::string stdin_partial;
    bool stdin_eof = command.has_value() || wait_running;
    int rc = 0;
    while (true) {
      if (wait_for_shutdown_signal(0.001) != 0) {
        say("leaving; the deputies keep running the last orders");
        break;
      }
      drain_status();
      int64_t now = mono_ns();
      bool changed = false;
      for (const auto& line : read_stdin_lines(stdin_partial, stdin_eof)) {
        std::istringstream words(line);
        std::string verb;
        std::string name;
        words >> verb >> name;
        if (verb.empty()) continue;
        const auto c = parse_command(verb);
        if (!c || name.empty()) {
          say("commands: start NAME, stop NAME, restart NAME (NAME or all)");
          continue;
        }
        try {
          sheriff.command(*c, name);
          say(verb + " " + name);
          changed = true;
        } catch (const std::invalid_argument& e) {
          say(e.what());
        }
      }
      if (now >= next_orders_ns || changed) {
        for (auto& o : sheriff.orders(command.has_value())) {
          o.utime = wall_us();
          bus.publish(channels::kDeputyOrders, o);
        }
        next_orders_ns = now + 1'000'000'000;
      }
      for (const auto& e : sheriff.host_events(now)) say(e);
      if (interactive && now >= next_table_ns) {
        std::printf("\033[H\033[2J%s", sheriff.table(now).c_str());
        std::fflush(stdout);
        next_table_ns = now + 1'000'000'000;
      } else if (!interactive && now >= next_table_ns) {
        const std::string sig = table_signature(sheriff, now);
        if (sig != printed_signature) {
          std::printf("%s", sheriff.table(now).c_str());
          std::fflush(stdout);
          printed_signature = sig;
        }
        next_table_ns = now + 200'000'000;
      }
      if (one_shot) {
        std::vector<std::string> waiting;
        if (sheriff.converged(now, &waiting)) {
          if (!interactive) std::printf("%s", sheriff.table(now).c_str());
          say(command ? command_word + " " + target + ": done" : "everything is running");
          break;
        }
        if (now - start_ns > static_cast<int64_t>(timeout_s * 1e9)) {
          std::printf("%s", sheriff.table(now).c_str());
          for (const auto& w : waiting) say("still waiting for " + w);
          say("timed out after " + std::to_string(static_cast<int>(timeout_s)) + " s");
          rc = 1;
          break;
        }
      }
      usleep(20'000);
    }
    // A last round of orders so a deputy that missed the others gets them.
    if (rc == 0 && one_shot)
      for (auto& o : sheriff.orders(command.has_value())) {
        o.utime = wall_us();
        bus.publish(channels::kDeputyOrders, o);
      }
    bus.stop();
    return rc;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "[sheriff] %s\n", e.what());
    return 1;
  }
}
