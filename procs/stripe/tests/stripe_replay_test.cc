// Replay of a recorded scan (the design card's replay-based testing), in a
// private network namespace, with the tools a user has:
//  1. a scan of the pyramid runs live (deploy/stripe.pbtxt headless, its
//     cloud written by the range process) while `lcm-logger` records the bus
//     (the launcher's --record);
//  2. fresh stripe and range processes are started and `lcm-logplayer`
//     plays the log's images and scan states (STRIPE_IMAGE, STRIPE_SCAN) to
//     them; the range process writes the cloud again.
// The two PLY files must be byte for byte the same.

#include <cstdio>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "tests/integration/harness.h"

namespace ephor::testing {
namespace {

namespace fs = std::filesystem;
using std::chrono::seconds;

constexpr const char* kUrl = "udpm://239.255.76.67:7676?ttl=0&recv_buf_size=16777216";

std::string bytes_of(const std::string& path) {
  std::string out;
  if (std::FILE* f = std::fopen(path.c_str(), "rb")) {
    char buf[65536];
    size_t n = 0;
    while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) out.append(buf, n);
    std::fclose(f);
  }
  return out;
}

TEST(StripeReplay, RecordedScanReplaysToAByteIdenticalCloud) {
  const fs::path dir =
      fs::temp_directory_path() / ("ephor-stripe-replay-" + std::to_string(getpid()));
  fs::create_directories(dir);
  const std::string log = (dir / "scan.lcm").string(), live = (dir / "live.ply").string(),
                    again = (dir / "replay.ply").string();
  const std::vector<std::pair<std::string, std::string>> env{{"LCM_DEFAULT_URL", kUrl}};
  {
    Processes p;
    p.start("launch", bin("ephor-launch"),
            {source_path("deploy/stripe.pbtxt"), "--headless", "--duration", "40", "--scene",
             source_path("deploy/stripe/scenes/pyramid.obj"), "--region=-30,-30,30,30",
             "--robot_seed", "1", "--out", live, "--record", log},
            env);
    ASSERT_TRUE(wait_until([&] { return p.exited("launch"); }, seconds(45)))
        << "the scan did not end";
    ASSERT_EQ(p.exits().front().code, 0);
  }
  const std::string live_bytes = bytes_of(live);
  ASSERT_GT(live_bytes.size(), 1000u) << live;
  {
    Processes p;
    p.start("stripe", bin("ephor-stripe-stripe"), {"--no-mlock", "--name", "stripe"}, env);
    p.start("range", bin("ephor-stripe-range"),
            {"--no-mlock", "--name", "range", "--robot-seed", "1", "--out", again}, env);
    ASSERT_TRUE(
        wait_until([&] { return p.has_line("stripe", "ready:") && p.has_line("range", "ready:"); },
                   seconds(10)));
    p.start("player", "/usr/bin/lcm-logplayer",
            {"--lcm-url", kUrl, "--regexp", "STRIPE_IMAGE|STRIPE_SCAN", log}, env);
    EXPECT_TRUE(wait_until([&] { return p.has_line("range", "written to"); }, seconds(30)))
        << "the replay did not give the cloud back";
  }
  EXPECT_EQ(bytes_of(again), live_bytes) << "live " << live << " vs replay " << again;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace ephor::testing
