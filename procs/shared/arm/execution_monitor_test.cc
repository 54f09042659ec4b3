#include "procs/shared/arm/execution_monitor.h"

#include <limits>

#include <gtest/gtest.h>

namespace ephor::arm {
namespace {

constexpr int64_t kT0 = 1'000'000'000;

ServoState servo_at(const Joints& q, int64_t traj, bool done) {
  ServoState s;
  s.q = q;
  s.trajectory_seq = traj;
  s.trajectory_done = done;
  return s;
}

TEST(ExecutionMonitorTest, DoneWhenTheServoFinishesAtTheTarget) {
  ExecutionMonitor m;
  Joints goal = Joints::Constant(0.5);
  m.set_plane(kPlaneObject);
  m.start(7, 70, 3, goal, 1.0, kT0);
  EXPECT_TRUE(m.busy());
  EXPECT_EQ(m.executing_seq(), 7);
  EXPECT_FALSE(m.on_servo(servo_at(Joints::Zero(), 3, false), kT0 + 100'000));
  EXPECT_FALSE(m.on_servo(servo_at(goal, 2, true), kT0 + 200'000));  // an older trajectory
  const auto ack = m.on_servo(servo_at(goal, 3, true), kT0 + 1'000'000);
  ASSERT_TRUE(ack);
  EXPECT_EQ(ack->status, AckStatus::kDone);
  EXPECT_EQ(ack->seq, 7);
  EXPECT_EQ(ack->goal_id, 70);
  EXPECT_FALSE(m.busy());
  EXPECT_EQ(m.last_done_seq(), 7);
  EXPECT_EQ(m.last_done_plane(), kPlaneObject);
}

TEST(ExecutionMonitorTest, FailsOnFaultOffTargetAndTimeout) {
  const Joints goal = Joints::Constant(0.5);
  ExecutionMonitor m;
  m.start(1, 1, 1, goal, 1.0, kT0);
  ServoState fault = servo_at(goal, 1, false);
  fault.fault = true;
  fault.fault_reason = "joint 2 over its velocity limit";
  auto ack = m.on_servo(fault, kT0);
  ASSERT_TRUE(ack);
  EXPECT_EQ(ack->status, AckStatus::kFailed);
  EXPECT_NE(ack->reason.find("joint 2 over"), std::string::npos);

  m.start(2, 2, 2, goal, 1.0, kT0);
  ack = m.on_servo(servo_at(Joints::Constant(0.4), 2, true), kT0);
  ASSERT_TRUE(ack);
  EXPECT_EQ(ack->status, AckStatus::kFailed);
  EXPECT_NE(ack->reason.find("from the target"), std::string::npos) << ack->reason;

  m.start(3, 3, 3, goal, 1.0, kT0);
  EXPECT_FALSE(m.on_tick(kT0 + 3'000'000));  // 1.0 * 1.5 + 2 s = 3.5 s
  ack = m.on_tick(kT0 + 3'600'000);
  ASSERT_TRUE(ack);
  EXPECT_EQ(ack->status, AckStatus::kFailed);
  EXPECT_NE(ack->reason.find("timed out"), std::string::npos);
  EXPECT_EQ(m.last_done_seq(), 0);
}

TEST(ExecutionMonitorTest, LatchedFaultOfAnEarlierTrajectoryIsNotOursAtFirst) {
  ExecutionMonitor m;
  const Joints goal = Joints::Constant(0.5);
  m.start(8, 8, 9, goal, 1.0, kT0);
  ServoState old_fault = servo_at(Joints::Zero(), 8, false);
  old_fault.fault = true;
  old_fault.fault_reason = "trajectory 8: joint 1 at its limit";
  EXPECT_FALSE(m.on_servo(old_fault, kT0 + 4'000));  // the servo has not taken trajectory 9 yet
  EXPECT_TRUE(m.busy());
  const auto ack = m.on_servo(old_fault, kT0 + 400'000);  // still not taken after the grace
  ASSERT_TRUE(ack);
  EXPECT_EQ(ack->status, AckStatus::kFailed);
}

TEST(ExecutionMonitorTest, PreemptedMotionFailsWithTheNewSeq) {
  ExecutionMonitor m;
  EXPECT_FALSE(m.preempt(5));
  m.start(4, 4, 4, Joints::Zero(), 1.0, kT0);
  const auto ack = m.preempt(5);
  ASSERT_TRUE(ack);
  EXPECT_EQ(ack->seq, 4);
  EXPECT_EQ(ack->reason, "replaced by command seq 5");
}

// Found by the fuzz target arm_process: a given trajectory of 3e38 s (its
// float times) overflowed the timeout's int64_t microseconds.
TEST(ExecutionMonitorTest, AnEndlessMotionNeverTimesOut) {
  ExecutionMonitor m;
  const Joints goal = Joints::Constant(0.5);
  m.start(7, 70, 3, goal, 3e38, kT0);
  EXPECT_FALSE(m.on_tick(kT0 + 1'000'000'000'000));
  EXPECT_FALSE(m.on_tick(std::numeric_limits<int64_t>::max() - 1));
  EXPECT_TRUE(m.busy());
  m.start(8, 80, 4, goal, 1.0, std::numeric_limits<int64_t>::max() - 1'000'000);
  EXPECT_FALSE(m.on_tick(std::numeric_limits<int64_t>::max() - 1));
  const auto ack = m.on_servo(servo_at(goal, 4, true), kT0);
  ASSERT_TRUE(ack);
  EXPECT_EQ(ack->status, AckStatus::kDone);
}

}  // namespace
}  // namespace ephor::arm
