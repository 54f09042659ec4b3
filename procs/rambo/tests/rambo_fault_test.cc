// Faults, nothing lost (issue 18 item 4, for the RAMBO system): the whole
// system (deploy/rambo.pbtxt, headless, the launcher's --restart as a deputy
// restarts) in a private network namespace, recorded by the launcher's
// lcm-logger without the camera. Every process but the simulator (the world,
// which ends the run) is killed with SIGKILL mid-run, one after the other.
// Each is running again within seconds and the loop goes on: poses and the
// arm's state flow again, and a diode is still tagged before the run ends by
// itself. The arm executes no goal twice, its own restart included (a
// restarted arm has lost its ledger; comm's retransmissions carry the first
// sending time and the arm refuses one older than its age limit), and the
// recorded log has no hole on RAMBO_POSE or ARM_STATE longer than a restart
// and the time the pose process needs for its first pose again.

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "common/lcm/bus.h"
#include "common/lcm/channels.h"
#include "common/rambo/rambo_channels.h"
#include "common/time/clock.h"
#include "ephor/arm_state_t.hpp"
#include "ephor/rambo_indicator_t.hpp"
#include "ephor/rambo_pose_t.hpp"
#include "tests/integration/harness.h"

namespace ephor::testing {
namespace {

namespace fs = std::filesystem;
using std::chrono::seconds;

// deploy/rambo.pbtxt's bus (this test has its network namespace to itself).
constexpr const char* kUrl = "udpm://239.255.76.67:7672?ttl=0&recv_buf_size=16777216";

TEST(RamboFaults, EachProcessKilledMidRunIsRestartedAndADiodeIsStillTagged) {
  const fs::path dir = fs::path("/dev/shm") / ("ephor-rambo-fault-" + std::to_string(getpid()));
  fs::create_directories(dir);
  const std::string log_path = (dir / "run.lcm").string();
  const std::string summary = (dir / "summary.json").string();

  std::mutex mutex;
  int64_t poses = 0, states = 0;
  int tagged = 0;
  Bus bus(kUrl, "fault-test");
  bus.subscribe<rambo_pose_t>(rambo::channels::kPose, [&](const rambo_pose_t&) {
    std::lock_guard<std::mutex> lock(mutex);
    ++poses;
  });
  bus.subscribe<arm_state_t>(channels::kArmState, [&](const arm_state_t&) {
    std::lock_guard<std::mutex> lock(mutex);
    ++states;
  });
  bus.subscribe<rambo_indicator_t>(rambo::channels::kIndicator, [&](const rambo_indicator_t& m) {
    std::lock_guard<std::mutex> lock(mutex);
    tagged = std::max(tagged, static_cast<int>(m.tagged_count));
  });
  bus.start();
  const auto heard = [&] {
    std::lock_guard<std::mutex> lock(mutex);
    return std::make_pair(poses, states);
  };

  Processes p;
  p.start("launch", bin("ephor-launch"),
          {source_path("deploy/rambo.pbtxt"), "--headless", "--restart", "--record", log_path,
           "--record-channels", "RAMBO_POSE|RAMBO_PREDICTION|RAMBO_INDICATOR|ARM_STATE|ARM_GOAL",
           "--seed", "1", "--max_s", "75", "--summary", summary},
          {{"LCM_DEFAULT_URL", kUrl}});
  // The camera runs at 5 Hz: ten poses are two seconds of the loop.
  ASSERT_TRUE(wait_until([&] { return heard().first >= 10 && heard().second >= 200; }, seconds(40)))
      << "poses and the arm's state did not start";
  const int64_t start_ns = mono_ns();

  std::map<std::string, double> restart_s_of;
  for (const std::string name : {"features", "pose", "predictor", "planner", "comm", "arm"}) {
    const auto before = heard();
    const int64_t t0 = mono_ns();
    const double restart_s = kill_and_await_restart(p, "launch", name, seconds(5));
    ASSERT_GE(restart_s, 0.0) << name << (restart_s < -1.5 ? " was not restarted" : " had no pid");
    restart_s_of[name] = restart_s;
    EXPECT_LT(restart_s, 5.0) << name;
    ASSERT_TRUE(wait_until(
        [&] {
          const auto now = heard();
          return now.first >= before.first + 5 && now.second >= before.second + 100;
        },
        seconds(15)))
        << "poses and arm states did not resume after " << name << " was killed";
    std::fprintf(stderr,
                 "%s (killed %.1f s in): kill -9 -> running again %.3f s, flowing again %.1f s\n",
                 name.c_str(), static_cast<double>(t0 - start_ns) * 1e-9, restart_s,
                 static_cast<double>(mono_ns() - t0) * 1e-9);
  }

  ASSERT_TRUE(wait_until([&] { return p.exited("launch"); }, seconds(90))) << "the run did not end";
  bus.stop();
  for (const auto& e : p.exits()) {
    if (e.name == "launch") {
      EXPECT_EQ(e.code, 0) << "the launcher reported a failure";
    }
  }

  const std::map<std::string, int> started = arm_goal_starts(p.lines("launch"));
  std::fprintf(stderr, "the arm set off on %zu goals\n", started.size());
  EXPECT_GE(started.size(), 3u) << "the arm was hardly sent anything";
  for (const auto& [goal, times] : started) EXPECT_EQ(times, 1) << "goal " << goal;

  nlohmann::json s;
  std::ifstream(summary) >> s;
  std::fprintf(stderr, "summary: tagged %d of %d\n", s["tagged"].get<int>(),
               s["diodes"].get<int>());
  EXPECT_GE(s["tagged"].get<int>(), 1) << "no diode tagged after the restarts";

  // Holes in the log: poses no longer than the slowest restart and the pose
  // process's first frames again (a second at 5 Hz, and frames where the
  // view gives no pose are still published as "no pose"), the arm's state no
  // longer than the arm's restart and a second.
  double slowest_s = 0.0;
  for (const auto& [name, seconds_] : restart_s_of) slowest_s = std::max(slowest_s, seconds_);
  const std::vector<std::pair<const char*, double>> bounds = {
      {rambo::channels::kPose, slowest_s + 2.0}, {channels::kArmState, restart_s_of["arm"] + 1.0}};
  for (const auto& [channel, bound_s] : bounds) {
    const ChannelGap g = longest_gap_in_log(log_path, channel);
    std::fprintf(stderr, "log: %d messages on %s, longest gap %.2f s at %.2f s (bound %.2f s)\n",
                 g.count, channel, g.longest_s, g.at_s, bound_s);
    EXPECT_GT(g.count, 50) << channel;
    EXPECT_LT(g.longest_s, bound_s) << channel;
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace ephor::testing
