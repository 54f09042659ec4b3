// End-to-end test of the planner -> comm -> arm path with the real processes:
// ephor-sim (the arm's servo), ephor-arm and ephor-comm in a private network
// namespace (NETNS). The test plays the planner: it publishes ARM_GOAL and
// waits for MOTION_DONE, one goal at a time as the planner does.

#include <chrono>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <limits>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "common/geometry/overhead_camera.h"
#include "common/geometry/workcell.h"
#include "common/lcm/bus.h"
#include "common/lcm/channels.h"
#include "common/time/clock.h"
#include "ephor/arm_cmd_t.hpp"
#include "ephor/arm_goal_t.hpp"
#include "ephor/arm_state_t.hpp"
#include "ephor/joint_trajectory_t.hpp"
#include "ephor/motion_done_t.hpp"
#include "tests/integration/harness.h"

namespace ephor::comm {
namespace {

using namespace std::chrono_literals;
using ephor::testing::wait_until;

constexpr int8_t kStatusDone = motion_done_t::STATUS_DONE;
constexpr int8_t kStatusRejected = motion_done_t::STATUS_REJECTED;
constexpr int8_t kElevation = arm_goal_t::PLANE_ELEVATION;
constexpr int8_t kObject = arm_goal_t::PLANE_OBJECT;

class CommArmTest : public ::testing::Test {
 protected:
  template <class F>
  auto locked(F f) {
    std::lock_guard<std::mutex> lock(mutex_);
    return f();
  }

  void SetUp() override {
    bus_.subscribe<motion_done_t>(channels::kMotionDone, [this](const motion_done_t& m) {
      locked([&] { done_.push_back(m); });
    });
    bus_.subscribe<arm_state_t>(channels::kArmState,
                                [this](const arm_state_t&) { locked([&] { ++states_; }); });
    bus_.subscribe<arm_cmd_t>(channels::kArmCmd,
                              [this](const arm_cmd_t& m) { locked([&] { cmds_.push_back(m); }); });
    bus_.subscribe<joint_trajectory_t>(channels::kArmTrajectory, [this](const joint_trajectory_t&) {
      locked([&] { ++trajectories_; });
    });
    bus_.start();
    procs_.start("sim", ephor::testing::bin("ephor-sim"), {"--sheep", "0", "--no-mlock"});
    procs_.start("arm", ephor::testing::bin("ephor-arm"), {"--no-mlock"});
    procs_.start("comm", ephor::testing::bin("ephor-comm"), {"--no-mlock"});
    ASSERT_TRUE(wait_until([this] { return locked([this] { return states_ > 10; }); }, 20s))
        << "no ARM_STATE from ephor-arm";
    ASSERT_TRUE(wait_until([this] { return procs_.has_line("comm", "arm 'arm' heard"); }, 10s))
        << "ephor-comm did not hear the arm";
  }

  void TearDown() override {
    if (HasFailure()) {
      for (const char* name : {"comm", "arm", "sim"})
        for (const auto& line : procs_.lines(name)) std::cerr << name << ": " << line << "\n";
    }
    bus_.stop();
    procs_.stop_all();
  }

  // Publishes a goal at field point (x, y) mm in `plane`, projected into the image.
  void send_goal(int64_t id, double x_mm, double y_mm, int8_t plane) {
    const double z = plane == kObject ? cell_.object_plane_z_mm : cell_.elevation_plane_z_mm;
    const Eigen::Vector2d uv = camera_.project(x_mm, y_mm, z);
    send_goal_uv(id, static_cast<float>(uv.x()), static_cast<float>(uv.y()), plane);
  }
  void send_goal_uv(int64_t id, float u, float v, int8_t plane) {
    arm_goal_t g{};
    g.utime = wall_us();
    g.goal_id = id;
    g.plane = plane;
    g.u = u;
    g.v = v;
    g.theta_rad = 0.0f;
    g.max_speed_mm_s = 0.0f;
    g.source_frame_utime = g.utime;
    g.target_object = -1;
    bus_.publish(channels::kArmGoal, g);
  }
  std::optional<motion_done_t> wait_done(int64_t id, std::chrono::milliseconds timeout = 30s) {
    std::optional<motion_done_t> out;
    wait_until(
        [&] {
          return locked([&] {
            for (const auto& d : done_)
              if (d.goal_id == id) out = d;
            return out.has_value();
          });
        },
        timeout);
    return out;
  }

  geometry::Workcell cell_;
  geometry::OverheadCamera camera_;
  ephor::testing::Processes procs_;
  Bus bus_{"", "planner"};
  std::mutex mutex_;
  std::vector<motion_done_t> done_;
  std::vector<arm_cmd_t> cmds_;
  int64_t states_ = 0;
  int64_t trajectories_ = 0;
};

TEST_F(CommArmTest, GoalsInTurnAreDoneEachWithOneMotion) {
  struct Target {
    double x, y;
    int8_t plane;
  };
  const std::vector<Target> targets = {
      {1000.0, 700.0, kElevation}, {1000.0, 200.0, kObject}, {1000.0, 700.0, kElevation}};
  std::vector<int64_t> seqs;
  for (size_t i = 0; i < targets.size(); ++i) {
    const int64_t id = static_cast<int64_t>(i) + 1;
    send_goal(id, targets[i].x, targets[i].y, targets[i].plane);
    const auto done = wait_done(id);
    ASSERT_TRUE(done) << "no MOTION_DONE for goal " << id;
    EXPECT_EQ(done->status, kStatusDone) << "goal " << id << ": " << done->reason;
    seqs.push_back(done->seq);
  }
  for (size_t i = 1; i < seqs.size(); ++i) EXPECT_EQ(seqs[i], seqs[i - 1] + 1);
  EXPECT_EQ(locked([&] { return trajectories_; }), static_cast<int64_t>(targets.size()))
      << "one motion per goal";
  locked([&] {
    for (const arm_cmd_t& c : cmds_) EXPECT_EQ(c.header.sender, "comm");
  });
  // comm logs each outcome just after publishing it.
  for (int64_t id = 1; id <= static_cast<int64_t>(targets.size()); ++id) {
    const std::string line =
        "goal " + std::to_string(id) + " seq " + std::to_string(seqs[id - 1]) + ": DONE";
    EXPECT_TRUE(wait_until([&] { return procs_.has_line("comm", line); }, 5s))
        << "no log line '" << line << "'";
  }
}

TEST_F(CommArmTest, TheArmsRefusalReachesThePlannerWithItsReason) {
  send_goal(1, cell_.field_length_mm + 40.0, 200.0, kObject);  // outside the field
  const auto done = wait_done(1);
  ASSERT_TRUE(done);
  EXPECT_EQ(done->status, kStatusRejected);
  EXPECT_FALSE(done->reason.empty());
  EXPECT_EQ(done->reason.find("invalid goal"), std::string::npos)
      << "a valid goal must be refused by the arm, not by comm: " << done->reason;
  EXPECT_EQ(done->attempts, 1);
  EXPECT_EQ(locked([&] { return trajectories_; }), 0) << "the arm moved for a refused goal";
}

TEST_F(CommArmTest, ANanGoalNeverReachesTheArm) {
  send_goal_uv(1, std::numeric_limits<float>::quiet_NaN(), 100.0f, kElevation);
  const auto refused = wait_done(1);
  ASSERT_TRUE(refused);
  EXPECT_EQ(refused->status, kStatusRejected);
  send_goal(2, 1000.0, 700.0, kElevation);
  const auto done = wait_done(2);
  ASSERT_TRUE(done);
  EXPECT_EQ(done->status, kStatusDone) << done->reason;
  locked([&] {
    for (const arm_cmd_t& c : cmds_) EXPECT_NE(c.goal_id, 1) << "the NaN goal reached ARM_CMD";
  });
}

}  // namespace
}  // namespace ephor::comm
