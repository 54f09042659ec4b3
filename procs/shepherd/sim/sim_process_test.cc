// Integration test of ephor-sim as a real process in a private network
// namespace (NETNS): frames and ground truth arrive paired, the servo state
// streams, trajectories are followed or refused, SIM_CMD changes the herd,
// and the process prints its summary on exit.

#include <chrono>
#include <cmath>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "common/lcm/bus.h"
#include "common/lcm/channels.h"
#include "common/time/clock.h"
#include "ephor/camera_frame_t.hpp"
#include "ephor/joint_state_t.hpp"
#include "ephor/joint_trajectory_t.hpp"
#include "ephor/shepherd_ground_truth_t.hpp"
#include "ephor/shepherd_sim_cmd_t.hpp"
#include "tests/integration/harness.h"

namespace ephor::sim {
namespace {

using namespace std::chrono_literals;
using ephor::testing::wait_until;

struct Seen {
  std::mutex mutex;
  std::vector<std::pair<int64_t, int64_t>> frames;  // (frame_index, utime)
  std::vector<std::pair<int64_t, int64_t>> truths;
  int64_t frame_bytes = 0;
  int32_t last_truth_sheep = -1;
  int64_t servo_count = 0;
  std::vector<int64_t> servo_mono_ns;
  std::optional<joint_state_t> servo;
};

joint_trajectory_t trajectory(int64_t seq, const std::vector<float>& t,
                              const std::vector<std::vector<double>>& q) {
  joint_trajectory_t m;
  m.utime = wall_us();
  m.seq = seq;
  m.num_points = static_cast<int32_t>(t.size());
  m.t_s = t;
  m.q = q;
  m.qd.assign(q.size(), std::vector<double>(6, 0.0));
  return m;
}

TEST(SimProcess, PublishesFramesTruthAndServoStateAndObeysCommands) {
  ephor::testing::Processes procs;
  procs.start("sim", ephor::testing::bin("ephor-sim"),
              {"--sheep", "3", "--seed", "2", "--no-mlock", "--fps", "30"});
  Bus bus("", "sim-test");
  Seen seen;
  bus.subscribe<camera_frame_t>(channels::kCamera, [&](const camera_frame_t& m) {
    std::lock_guard<std::mutex> lock(seen.mutex);
    seen.frames.emplace_back(m.frame_index, m.utime);
    seen.frame_bytes = m.size;
  });
  bus.subscribe<shepherd_ground_truth_t>(channels::kGroundTruth,
                                         [&](const shepherd_ground_truth_t& m) {
                                           std::lock_guard<std::mutex> lock(seen.mutex);
                                           seen.truths.emplace_back(m.frame_index, m.utime);
                                           seen.last_truth_sheep = m.num_sheep;
                                         });
  bus.subscribe<joint_state_t>(channels::kArmServo, [&](const joint_state_t& m) {
    std::lock_guard<std::mutex> lock(seen.mutex);
    ++seen.servo_count;
    seen.servo_mono_ns.push_back(mono_ns());
    seen.servo = m;
  });
  bus.start();
  const auto locked = [&](auto f) {
    std::lock_guard<std::mutex> lock(seen.mutex);
    return f();
  };

  ASSERT_TRUE(wait_until([&] { return locked([&] { return seen.truths.size() >= 15; }); }, 10s))
      << "no ground truth from ephor-sim";
  locked([&] {
    EXPECT_EQ(seen.frame_bytes, 512 * 482);
    EXPECT_EQ(seen.last_truth_sheep, 3);
    // Every truth pairs with the frame of the same index and capture time.
    int paired = 0;
    for (const auto& t : seen.truths)
      for (const auto& f : seen.frames)
        if (f.first == t.first) {
          EXPECT_EQ(f.second, t.second) << "frame " << f.first;
          ++paired;
        }
    EXPECT_GE(paired, 10);
    return 0;
  });

  // ARM_SERVO streams at 250 Hz; accept >= 100 Hz on a loaded test machine.
  ASSERT_TRUE(wait_until([&] { return locked([&] { return seen.servo_count >= 300; }); }, 10s));
  locked([&] {
    const auto& t = seen.servo_mono_ns;
    const double rate =
        static_cast<double>(t.size() - 1) * 1e9 / static_cast<double>(t.back() - t.front());
    EXPECT_GT(rate, 100.0);
    EXPECT_FALSE(seen.servo->fault);
    return 0;
  });
  std::vector<double> q0(seen.servo->q, seen.servo->q + 6);

  // Malformed: times not increasing. Logged, ignored, no fault.
  auto bad = trajectory(5, {0.5f, 0.2f}, {q0, q0});
  bus.publish(channels::kArmTrajectory, bad);
  EXPECT_TRUE(
      wait_until([&] { return procs.has_line("sim", "ARM_TRAJECTORY seq 5 ignored"); }, 5s));

  // A gentle move of joint 1 is followed to the end.
  std::vector<double> q1 = q0;
  q1[0] += 0.2;
  auto good = trajectory(7, {1.0f}, {q1});
  bus.publish(channels::kArmTrajectory, good);
  ASSERT_TRUE(wait_until(
      [&] {
        return locked(
            [&] { return seen.servo->trajectory_seq == 7 && seen.servo->trajectory_done != 0; });
      },
      10s));
  locked([&] {
    EXPECT_NEAR(seen.servo->q[0], q1[0], 1e-3);
    EXPECT_FALSE(seen.servo->fault) << seen.servo->fault_reason;
    return 0;
  });

  // Out of the joint limits: refused with a fault, the arm holds still.
  std::vector<double> q2 = q1;
  q2[1] = 10.0;
  auto out = trajectory(8, {1.0f}, {q2});
  bus.publish(channels::kArmTrajectory, out);
  ASSERT_TRUE(wait_until(
      [&] { return locked([&] { return seen.servo->trajectory_seq == 8 && seen.servo->fault; }); },
      10s));
  locked([&] {
    EXPECT_NE(seen.servo->fault_reason.find("outside"), std::string::npos);
    EXPECT_NEAR(seen.servo->q[1], q1[1], 1e-3);
    return 0;
  });

  // SIM_CMD: five sheep.
  shepherd_sim_cmd_t cmd;
  cmd.utime = wall_us();
  cmd.sheep = 5;
  cmd.reset = false;
  cmd.seed = 0;
  bus.publish(channels::kSimCmd, cmd);
  EXPECT_TRUE(wait_until([&] { return locked([&] { return seen.last_truth_sheep == 5; }); }, 10s));

  bus.stop();
  procs.stop_all();
  EXPECT_TRUE(procs.has_line("sim", "summary: escapes"));
}

}  // namespace
}  // namespace ephor::sim
