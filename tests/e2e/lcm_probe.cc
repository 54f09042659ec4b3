// ephor-e2e-probe: watches LCM for the display's end-to-end test, so the test
// checks what really went over the bus rather than what the page says.
//
//   ephor-e2e-probe --want silent   --channel BLOBS [--window-s 1] [--timeout-s 5]
//       succeeds once `window-s` pass with no message on the channel
//   ephor-e2e-probe --want messages --channel BLOBS [--min 10] [--timeout-s 5]
//       succeeds once `min` messages arrived
//   ephor-e2e-probe --want mode=1   [--timeout-s 5]
//       succeeds once a shepherd_blobs_t with that mode (shepherd_vision_cmd_t.MODE_*) arrived
//   ephor-e2e-probe --want count    [--window-s 2]
//       counts every channel for `window-s`; always succeeds
// Prints "listening" when subscribed, then one JSON line: {"ok":…, "counts":{…},
// "blobs_mode":…}. Exit status 0 when the wanted thing happened, 1 if not, 2 on
// a usage error.

#include <chrono>
#include <iostream>
#include <map>
#include <string>

#include <CLI/CLI.hpp>
#include <lcm/lcm-cpp.hpp>
#include <nlohmann/json.hpp>

#include "common/lcm/bus.h"
#include "common/runtime/process_args.h"
#include "ephor/shepherd_blobs_t.hpp"

namespace {

using Clock = std::chrono::steady_clock;

struct Probe {
  std::map<std::string, int64_t> counts;
  std::string channel = "BLOBS";
  int blobs_mode = -1;
  Clock::time_point last_on_channel{};

  void on_message(const lcm::ReceiveBuffer* rbuf, const std::string& ch) {
    ++counts[ch];
    if (ch == channel) last_on_channel = Clock::now();
    if (ch == "BLOBS") {
      ephor::shepherd_blobs_t m;
      if (m.decode(rbuf->data, 0, static_cast<int>(rbuf->data_size)) > 0) blobs_mode = m.mode;
    }
  }
};

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"ephor-e2e-probe: checks LCM traffic for the display's browser test"};
  std::string want = "count";
  Probe probe;
  double window_s = 1.0;
  double timeout_s = 5.0;
  int64_t min = 10;
  std::string url;
  app.add_option("--want", want, "silent, messages, mode=N or count");
  app.add_option("--channel", probe.channel, "channel for silent/messages (default BLOBS)");
  app.add_option("--window-s", window_s, "quiet window (silent) or counting time (count), s");
  app.add_option("--timeout-s", timeout_s, "give up after this long, s");
  app.add_option("--min", min, "messages wanted (messages)");
  app.add_option("--lcm-url", url, "LCM URL (default as every ephor process)");
  if (const auto exit_status = ephor::parse_flags(app, argc, argv)) return *exit_status;
  int want_mode = -1;
  if (want.rfind("mode=", 0) == 0) {
    want_mode = std::stoi(want.substr(5));
  } else if (want != "silent" && want != "messages" && want != "count") {
    std::cerr << "unknown --want '" << want << "'\n";
    return 2;
  }

  lcm::LCM lcm(ephor::resolve_lcm_url(url));
  if (!lcm.good()) {
    std::cerr << "cannot open LCM\n";
    return 2;
  }
  lcm.subscribe(".*", &Probe::on_message, &probe);
  std::cout << "listening" << std::endl;

  const auto start = Clock::now();
  const auto seconds_since = [](Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
  };
  bool ok = false;
  while (true) {
    lcm.handleTimeout(20);
    if (want == "count") {
      if (seconds_since(start) >= window_s) {
        ok = true;
        break;
      }
    } else if (want == "silent") {
      const auto quiet_since = probe.counts[probe.channel] == 0 ? start : probe.last_on_channel;
      if (seconds_since(quiet_since) >= window_s) {
        ok = true;
        break;
      }
    } else if (want == "messages") {
      if (probe.counts[probe.channel] >= min) {
        ok = true;
        break;
      }
    } else if (probe.blobs_mode == want_mode) {
      ok = true;
      break;
    }
    if (want != "count" && seconds_since(start) >= timeout_s) break;
  }
  nlohmann::json out = {{"ok", ok},
                        {"want", want},
                        {"elapsed_s", seconds_since(start)},
                        {"counts", probe.counts},
                        {"blobs_mode", probe.blobs_mode}};
  std::cout << out.dump() << std::endl;
  return ok ? 0 : 1;
}
