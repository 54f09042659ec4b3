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
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "common/lcm/channels.h"
#include "common/rambo/rambo_channels.h"
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

  ChannelCounter heard(kUrl, {rambo::channels::kPose, channels::kArmState});

  Processes p;
  p.start("launch", bin("ephor-launch"),
          {source_path("deploy/rambo.pbtxt"), "--headless", "--restart", "--record", log_path,
           "--record-channels", "RAMBO_POSE|RAMBO_PREDICTION|RAMBO_INDICATOR|ARM_STATE|ARM_GOAL",
           "--seed", "1", "--max_s", "75", "--summary", summary},
          {{"LCM_DEFAULT_URL", kUrl}});
  // The camera runs at 5 Hz: ten poses are two seconds of the loop.
  ASSERT_TRUE(wait_until(
      [&] {
        return heard.reached({{rambo::channels::kPose, 10}, {channels::kArmState, 200}});
      },
      seconds(40)))
      << "poses and the arm's state did not start";
  const std::vector<std::string> victims = {"features", "pose", "predictor",
                                            "planner",  "comm", "arm"};
  const std::map<std::string, double> restart_s_of = kill_each_in_turn(
      p, "launch", victims, heard, {{rambo::channels::kPose, 5}, {channels::kArmState, 100}});
  ASSERT_EQ(restart_s_of.size(), victims.size()) << "not every process came back";

  ASSERT_TRUE(wait_until([&] { return p.exited("launch"); }, seconds(90))) << "the run did not end";
  expect_clean_exit(p, "launch");

  expect_each_goal_once(p, "launch", 3);

  nlohmann::json s;
  std::ifstream(summary) >> s;
  std::fprintf(stderr, "summary: tagged %d of %d\n", s["tagged"].get<int>(),
               s["diodes"].get<int>());
  EXPECT_GE(s["tagged"].get<int>(), 1) << "no diode tagged after the restarts";

  // Holes in the log: poses no longer than the slowest restart and the pose
  // process's first frames again (a second at 5 Hz, and frames where the
  // view gives no pose are still published as "no pose"), the arm's state no
  // longer than the arm's restart and a second.
  expect_log_gaps_within(log_path,
                         {{rambo::channels::kPose, slowest_restart_s(restart_s_of) + 2.0},
                          {channels::kArmState, restart_s_of.at("arm") + 1.0}},
                         51);
  fs::remove_all(dir);
}

// 5 % of the packets on the bus dropped: the loop goes on (poses, the arm
// commanded), every process stays up, a diode is tagged and no goal runs
// twice.
TEST(RamboFaults, FivePercentPacketLossStillTagsADiode) {
  const PacketLoss loss(0.05);  // until the end of the test
  const std::string summary = write_temp_file("rambo_loss_summary.json", "");
  Processes p;
  p.start("launch", bin("ephor-launch"),
          {source_path("deploy/rambo.pbtxt"), "--headless", "--seed", "1", "--max_s", "45",
           "--summary", summary},
          {{"LCM_DEFAULT_URL", kUrl}});
  ASSERT_TRUE(wait_until([&] { return p.exited("launch"); }, seconds(75))) << "the run did not end";
  expect_clean_exit(p, "launch", "under packet loss");
  const size_t goals = expect_each_goal_once(p, "launch", 3);
  nlohmann::json s;
  std::ifstream(summary) >> s;
  std::fprintf(stderr, "with 5 %% loss: tagged %d of %d, poses found %d of %d, arm goals %zu\n",
               s["tagged"].get<int>(), s["diodes"].get<int>(), s["poses_found"].get<int>(),
               s["poses"].get<int>(), goals);
  EXPECT_GE(s["tagged"].get<int>(), 1) << "no diode tagged under packet loss";
}

}  // namespace
}  // namespace ephor::testing
