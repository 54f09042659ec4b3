// Replay of a recorded scan (issue 15, the design card's replay-based
// testing), in a private network namespace, with the tools a user has:
//  1. the ranger and the locator run live (the sphere 5 m out, Scan Line
//     Extent improved) while `lcm-logger` records the bus;
//  2. a fresh locator is started and `lcm-logplayer` plays the log's scan
//     lines (SPHERE_SCAN_LINE only) to it; its estimates are heard.
// Every estimate of the live run must come back byte-identical from the
// replay, except the fields that say when and how long, not what: the
// publish times (utime, header.utime), the per-sender sequence number and
// the algorithm's CPU time (cpu_us).

#include <csignal>
#include <filesystem>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>

#include "common/lcm/bus.h"
#include "common/sphere/sphere_channels.h"
#include "ephor/sphere_estimate_t.hpp"
#include "tests/integration/harness.h"

namespace ephor::testing {
namespace {

namespace fs = std::filesystem;
using std::chrono::seconds;

constexpr const char* kUrl = "udpm://239.255.76.67:7671?ttl=0&recv_buf_size=16777216";
constexpr int kWindows = 8;  // estimates recorded live (4 s of scanning)

// The estimate's bytes without the fields that depend on when it was made.
std::vector<uint8_t> what_not_when(sphere_estimate_t m) {
  m.utime = 0;
  m.header.utime = 0;
  m.header.seq = 0;
  m.cpu_us = 0.0F;
  std::vector<uint8_t> bytes(static_cast<size_t>(m.getEncodedSize()));
  m.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  return bytes;
}

// Estimates by window, from a log file or heard on the bus.
std::map<int64_t, sphere_estimate_t> estimates_in_log(const std::string& path, int* scan_lines) {
  std::map<int64_t, sphere_estimate_t> out;
  *scan_lines = 0;
  lcm::LogFile log(path, "r");
  EXPECT_TRUE(log.good()) << path;
  if (!log.good()) return out;
  while (const lcm::LogEvent* e = log.readNextEvent()) {
    if (e->channel == sphere::channels::kScanLine) ++*scan_lines;
    if (e->channel != sphere::channels::kEstimate) continue;
    sphere_estimate_t m;
    if (m.decode(e->data, 0, static_cast<int>(e->datalen)) == static_cast<int>(e->datalen))
      out[m.window] = m;
  }
  return out;
}

TEST(SphereReplay, RecordedScanLinesReplayToByteIdenticalEstimates) {
  const fs::path dir =
      fs::temp_directory_path() / ("ephor-sphere-replay-" + std::to_string(getpid()));
  fs::create_directories(dir);
  const std::string log_path = (dir / "run.lcm").string();
  const std::vector<std::pair<std::string, std::string>> env{{"LCM_DEFAULT_URL", kUrl}};

  // 1. The live run, recorded.
  {
    Processes p;
    p.start("logger", "/usr/bin/lcm-logger", {"--force", "--lcm-url", kUrl, log_path}, env);
    p.start("locator", bin("ephor-sphere-locator"),
            {"--no-mlock", "--name", "locator", "--algorithm", "sle", "--variant", "improved"},
            env);
    std::mutex mutex;
    int heard = 0;
    Bus bus(kUrl, "replay-test");
    bus.subscribe<sphere_estimate_t>(sphere::channels::kEstimate, [&](const sphere_estimate_t&) {
      std::lock_guard<std::mutex> lock(mutex);
      ++heard;
    });
    bus.start();
    // The logger and the locator listen before the first line is measured:
    // the ranger last.
    ASSERT_TRUE(wait_until(
        [&] { return p.has_line("logger", "Opening log file") && p.has_line("locator", "ready:"); },
        seconds(10)));
    p.start("ranger", bin("ephor-sphere-ranger"),
            {"--no-mlock", "--name", "ranger", "--seed", "4", "--start-m", "5"}, env);
    ASSERT_TRUE(wait_until(
        [&] {
          std::lock_guard<std::mutex> lock(mutex);
          return heard >= kWindows;
        },
        seconds(30)))
        << "the live run made fewer than " << kWindows << " estimates";
    p.signal("ranger", SIGINT);
    ASSERT_TRUE(wait_until(
        [&] {
          for (const auto& e : p.exits())
            if (e.name == "ranger") return true;
          return false;
        },
        seconds(10)));
    bus.stop();
    p.stop_all();  // SIGINT: lcm-logger closes its file
  }
  int scan_lines = 0;
  const std::map<int64_t, sphere_estimate_t> live = estimates_in_log(log_path, &scan_lines);
  ASSERT_GE(live.size(), static_cast<size_t>(kWindows)) << "estimates in the log";
  ASSERT_GE(scan_lines, 50 * kWindows) << "scan lines in the log";

  // 2. The log's scan lines through a fresh locator.
  std::map<int64_t, sphere_estimate_t> replayed;
  {
    Processes p;
    std::mutex mutex;
    Bus bus(kUrl, "replay-test");
    bus.subscribe<sphere_estimate_t>(sphere::channels::kEstimate, [&](const sphere_estimate_t& m) {
      std::lock_guard<std::mutex> lock(mutex);
      replayed[m.window] = m;
    });
    bus.start();
    p.start("locator", bin("ephor-sphere-locator"),
            {"--no-mlock", "--name", "locator", "--algorithm", "sle", "--variant", "improved"},
            env);
    ASSERT_TRUE(wait_until([&] { return p.has_line("locator", "ready:"); }, seconds(10)));
    p.start("player", "/usr/bin/lcm-logplayer",
            {"--lcm-url", kUrl, "--regexp", sphere::channels::kScanLine, log_path}, env);
    const auto all_back = [&] {
      std::lock_guard<std::mutex> lock(mutex);
      for (const auto& [window, m] : live)
        if (replayed.count(window) == 0) return false;
      return true;
    };
    EXPECT_TRUE(wait_until(all_back, seconds(30))) << "the replay did not give every window back";
    bus.stop();
  }

  // Every live estimate, byte for byte (what, not when).
  int compared = 0, ok = 0;
  for (const auto& [window, m] : live) {
    const auto it = replayed.find(window);
    if (it == replayed.end()) continue;
    ++compared;
    ok += m.ok ? 1 : 0;
    EXPECT_EQ(what_not_when(m), what_not_when(it->second))
        << "window " << window << ": live (" << m.position_m[0] << ", " << m.position_m[1] << ", "
        << m.position_m[2] << ") vs replay (" << it->second.position_m[0] << ", "
        << it->second.position_m[1] << ", " << it->second.position_m[2] << ")";
  }
  EXPECT_EQ(compared, static_cast<int>(live.size()));
  EXPECT_GE(ok, kWindows - 1) << "live estimates with a position (the first window may be partial)";
  fs::remove_all(dir);
}

}  // namespace
}  // namespace ephor::testing
