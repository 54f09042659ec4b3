// ArmProcess (arm_process.h) run by hand, as the fuzz target arm_process runs
// it: its handlers and tasks called in turn on a fake clock (us), what it
// publishes recorded. The process with its servo on a real bus is
// arm_process_test.cc.

#include "procs/shared/arm/arm_process.h"

#include <cstdint>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "common/arm/arm_workcell.h"

namespace ephor::arm {
namespace {

constexpr int64_t kWallStartUs = 1'700'000'000'000'000;  // the arm's start, wall clock, us

struct Recorder : ArmOutputs {
  std::vector<arm_ack_t> acks;
  std::vector<std::pair<joint_trajectory_t, bool>> trajectories;
  int states = 0;
  bool released = false;
  bool publish_state(arm_state_t&) override { return ++states > 0; }
  bool publish_ack(arm_ack_t& m) override {
    acks.push_back(m);
    return true;
  }
  bool publish_trajectory(joint_trajectory_t& m, bool stop) override {
    trajectories.emplace_back(m, stop);
    return true;
  }
  void command_queued() override { released = true; }
};

class ArmProcessHandlersTest : public ::testing::Test {
 protected:
  void servo_at(const Joints& q) {
    joint_state_t s{};
    s.utime = wall_us_;
    for (int j = 0; j < 6; ++j) s.q[j] = q[j];
    arm_.on_servo(s);
  }
  arm_cmd_t joints_command(int64_t seq, const Joints& q) const {
    arm_cmd_t c{};
    c.utime = wall_us_;
    c.header.sender = "comm";
    c.seq = seq;
    c.goal_id = 10 * seq;
    c.kind = kKindJoints;
    for (int j = 0; j < 6; ++j) c.joints_rad[j] = q[j];
    return c;
  }
  void advance(int64_t us) {
    mono_us_ += us;
    wall_us_ += us;
  }

  geometry::Workcell cell_;
  geometry::OverheadCamera camera_;
  Joints park_ = park_joints(cell_);
  int64_t mono_us_ = 1'000'000'000;
  int64_t wall_us_ = kWallStartUs;
  Recorder out_;
  ArmProcess arm_{out_,
                  cell_,
                  calibration::FieldCalibration::from_camera(camera_, cell_),
                  camera_,
                  ArmProcessOptions{},
                  {[this] { return mono_us_; }, [this] { return wall_us_; }}};
};

TEST_F(ArmProcessHandlersTest, AJointCommandIsPlannedSentAndAccepted) {
  servo_at(park_);
  advance(10'000);
  Joints goal = park_;
  goal[0] += 0.2;
  arm_.on_command(joints_command(1, goal));
  EXPECT_TRUE(out_.released);
  arm_.command_job();
  ASSERT_EQ(out_.trajectories.size(), 1u);
  EXPECT_FALSE(out_.trajectories[0].second);
  EXPECT_EQ(out_.trajectories[0].first.seq, kWallStartUs + 1);
  ASSERT_EQ(out_.acks.size(), 1u);
  EXPECT_EQ(out_.acks[0].status, static_cast<int8_t>(arm_ack_t::STATUS_ACCEPTED));
  EXPECT_EQ(out_.acks[0].goal_id, 10);
  arm_.state_job();
  EXPECT_EQ(out_.states, 1);
}

// Found by the fuzz target arm_process: the command's age was taken before
// its send time was checked, and a utime of INT64_MIN overflowed it.
TEST_F(ArmProcessHandlersTest, ACommandSentAtInt64MinIsRejectedForItsSendTime) {
  servo_at(park_);
  advance(10'000);
  arm_cmd_t c = joints_command(1, park_);
  c.utime = std::numeric_limits<int64_t>::min();
  arm_.on_command(c);
  arm_.command_job();
  ASSERT_EQ(out_.acks.size(), 1u);
  EXPECT_EQ(out_.acks[0].status, static_cast<int8_t>(arm_ack_t::STATUS_REJECTED));
  EXPECT_EQ(out_.acks[0].reason, "command has no send time (utime <= 0)");
  EXPECT_TRUE(out_.trajectories.empty());
}

TEST_F(ArmProcessHandlersTest, AnEstopSendsAStopAndRefusesCommandsUntilReleased) {
  servo_at(park_);
  advance(10'000);
  estop_t e{};
  e.header.sender = "display";
  e.stop = true;
  arm_.on_estop(e);
  ASSERT_EQ(out_.trajectories.size(), 1u);
  EXPECT_TRUE(out_.trajectories[0].second);
  EXPECT_EQ(out_.trajectories[0].first.num_points, 1);
  Joints goal = park_;
  goal[0] += 0.2;
  arm_.on_command(joints_command(1, goal));
  arm_.command_job();
  ASSERT_EQ(out_.acks.size(), 1u);
  EXPECT_EQ(out_.acks[0].status, static_cast<int8_t>(arm_ack_t::STATUS_REJECTED));
  EXPECT_EQ(out_.trajectories.size(), 1u);
  e.stop = false;
  arm_.on_estop(e);
  advance(10'000);
  arm_.on_command(joints_command(2, goal));
  arm_.command_job();
  ASSERT_EQ(out_.acks.size(), 2u);
  EXPECT_EQ(out_.acks[1].status, static_cast<int8_t>(arm_ack_t::STATUS_ACCEPTED));
  ASSERT_EQ(out_.trajectories.size(), 2u);
  EXPECT_FALSE(out_.trajectories[1].second);
}

}  // namespace
}  // namespace ephor::arm
