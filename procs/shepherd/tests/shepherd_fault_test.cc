// Faults, nothing lost (issue 18 item 4, for the shepherding system): the
// whole system (deploy/shepherd.pbtxt, headless, the launcher's --restart as
// a deputy restarts) in a private network namespace, recorded by the
// launcher's lcm-logger (without the camera: --record-channels).
//
// 1. Every process but the simulator (the world itself) is killed with
//    SIGKILL mid-run, one after the other, the monitor first so that its
//    summary covers the rest. Each is running again within seconds; the
//    world model's objects and the arm's state flow again; the arm executes
//    no goal twice, its own restart included (every "seq S goal G: ... move"
//    it logs is a different G); the recorded log has no hole on OBJECTS or
//    ARM_STATE longer than a restart and a second.
// 2. 5 % of the packets on the bus dropped (iptables' statistic match in this
//    test's network namespace): a camera frame is five LCM fragments, so a
//    frame is lost more often than a packet; the world model still tracks the
//    sheep, the arm is still commanded and no process fails.

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "common/lcm/channels.h"
#include "tests/integration/harness.h"

namespace ephor::testing {
namespace {

namespace fs = std::filesystem;
using std::chrono::seconds;

// deploy/shepherd.pbtxt's bus (this test has its network namespace to itself).
constexpr const char* kUrl = "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=16777216";

nlohmann::json read_summary(const std::string& path) {
  nlohmann::json s;
  std::ifstream(path) >> s;
  return s;
}

TEST(ShepherdFaults, EachProcessKilledMidRunIsRestartedAndNoGoalRunsTwice) {
  const fs::path dir = fs::path("/dev/shm") / ("ephor-shepherd-fault-" + std::to_string(getpid()));
  fs::create_directories(dir);
  const std::string log_path = (dir / "run.lcm").string();
  const std::string summary = (dir / "summary.json").string();

  ChannelCounter heard(kUrl, {channels::kObjects, channels::kArmState});
  Processes p;
  p.start("launch", bin("ephor-launch"),
          {source_path("deploy/shepherd.pbtxt"), "--headless", "--restart", "--record", log_path,
           "--record-channels", "OBJECTS|ARM_STATE|ARM_GOAL|GROUND_TRUTH", "--duration", "45",
           "--seed", "7", "--sheep", "4", "--summary", summary});
  ASSERT_TRUE(wait_until(
      [&] {
        return heard.reached({{channels::kObjects, 60}, {channels::kArmState, 200}});
      },
      seconds(40)))
      << "the world model and the arm did not start";
  const std::vector<std::string> victims = {"monitor", "vision", "worldmodel",
                                            "planner", "comm",   "arm"};
  const std::map<std::string, double> restart_s_of = kill_each_in_turn(
      p, "launch", victims, heard, {{channels::kObjects, 30}, {channels::kArmState, 100}});
  ASSERT_EQ(restart_s_of.size(), victims.size()) << "not every process came back";

  ASSERT_TRUE(wait_until([&] { return p.exited("launch"); }, seconds(70))) << "the run did not end";
  expect_clean_exit(p, "launch");

  // No goal executed twice ("[arm ...] seq 14 goal 14: cartesian move to ...").
  expect_each_goal_once(p, "launch", 6);

  const nlohmann::json s = read_summary(summary);
  std::fprintf(stderr, "summary after the monitor's restart: saves %d, escapes %d\n",
               s["saves"].get<int>(), s["escapes"].get<int>());
  EXPECT_GE(s["saves"].get<int>(), 1) << "no sheep saved after the restarts";

  // Holes in the log: no longer than the slowest restart in the chain and a
  // second (objects, 30 Hz), the arm's restart and a second (its state, 100 Hz).
  expect_log_gaps_within(log_path,
                         {{channels::kObjects, slowest_restart_s(restart_s_of) + 1.0},
                          {channels::kArmState, restart_s_of.at("arm") + 1.0}},
                         601);
  fs::remove_all(dir);
}

TEST(ShepherdFaults, FivePercentPacketLossStillTracksAndCommandsTheArm) {
  const PacketLoss loss(0.05);  // until the end of the test
  const fs::path dir = fs::path("/dev/shm") / ("ephor-shepherd-loss-" + std::to_string(getpid()));
  fs::create_directories(dir);
  const std::string summary = (dir / "summary.json").string();
  Processes p;
  p.start("launch", bin("ephor-launch"),
          {source_path("deploy/shepherd.pbtxt"), "--headless", "--duration", "30", "--seed", "7",
           "--sheep", "4", "--summary", summary});
  ASSERT_TRUE(wait_until([&] { return p.exited("launch"); }, seconds(75))) << "the run did not end";
  const nlohmann::json s = read_summary(summary);
  std::fprintf(stderr, "with 5 %% loss: objects %.1f Hz, saves %d, escapes %d, id switches %d\n",
               s["objects_rate_hz"].get<double>(), s["saves"].get<int>(), s["escapes"].get<int>(),
               s["id_switches"].get<int>());
  // A frame lost with any of its five fragments, BLOBS and OBJECTS dropped
  // too, and the monitor's own copy: 17.5 Hz of 30 were heard in one run.
  EXPECT_GT(s["objects_rate_hz"].get<double>(), 10.0);
  // The arm goes on being commanded and finishing its moves. Saves and
  // escapes are printed, not asserted: which packets are lost is not seeded,
  // and one lost MOTION_DONE early in seed 7's opening burst (4 s until
  // comm's deadline) has cost two sheep in one run of four and none in the
  // others. At 8 mm/s a 30 s run of seed 7 needs few moves (a save is
  // three: over, down, up, and the first move over is a 6 s joint-space
  // swing): runs with 5 % loss gave 2 to 6 commands, and 0 or 1 saves.
  EXPECT_GE(s["arm_commands"].get<int>(), 2) << "the arm stopped being commanded";
  expect_clean_exit(p, "launch", "under packet loss");
  fs::remove_all(dir);
}

}  // namespace
}  // namespace ephor::testing
