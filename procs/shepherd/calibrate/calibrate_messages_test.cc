// CellInputs (ephor-calibrate's handlers) and trajectory_message_of().

#include "procs/shepherd/calibrate/calibrate_messages.h"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "common/arm/puma560.h"

namespace ephor::calibrate {
namespace {

camera_frame_t frame(int w, int h, size_t bytes, int64_t utime) {
  camera_frame_t m;
  m.utime = utime;
  m.width = w;
  m.height = h;
  m.data.assign(bytes, 7);
  m.size = static_cast<int32_t>(bytes);
  return m;
}

TEST(CellInputs, KeepsTheNewestWholeFrameAndCountsTheOthers) {
  CellInputs in;
  EXPECT_EQ(in.frame_utime(), 0);
  EXPECT_TRUE(in.on_frame(frame(4, 3, 12, 100)));
  EXPECT_FALSE(in.on_frame(frame(4, 3, 11, 200)));
  EXPECT_FALSE(in.on_frame(frame(0, 3, 0, 300)));
  EXPECT_FALSE(in.on_frame(frame(-4, -3, 12, 400)));
  EXPECT_EQ(in.bad_frames(), 3);
  EXPECT_EQ(in.frame_utime(), 100);
  const GreyFrame f = in.frame();
  EXPECT_EQ(f.width, 4);
  EXPECT_EQ(f.height, 3);
  EXPECT_EQ(f.data.size(), 12u);
}

TEST(CellInputs, DropsAStateWhoseJointsAreNotFinite) {
  CellInputs in;
  EXPECT_FALSE(in.state());
  joint_state_t m;
  m.utime = 1;
  for (int j = 0; j < 6; ++j) m.q[j] = 0.1 * j;
  EXPECT_TRUE(in.on_state(m));
  joint_state_t bad = m;
  bad.utime = 2;
  bad.q[4] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(in.on_state(bad));
  ASSERT_TRUE(in.state());
  EXPECT_EQ(in.state()->utime, 1);
  EXPECT_DOUBLE_EQ(joints_of(*in.state())(5), 0.5);
}

// Fuzz finding (crash-start-just-above-joint-limit): a servo state within
// JointMove's 1e-6 rad above a limit became a trajectory whose first point
// the servo refuses, stopping the arm with a fault.
TEST(MoveStart, ClampsAStateJustOutsideTheLimitsAndRefusesOneFarther) {
  const arm::JointLimits lim = arm::Puma560::default_limits();
  joint_state_t m;
  for (int j = 0; j < 6; ++j) m.q[j] = 0.5 * (lim.q_min(j) + lim.q_max(j));
  m.q[3] = lim.q_max(3) + 5e-7;
  const arm::Joints start = move_start_of(m, lim);
  EXPECT_EQ(start(3), lim.q_max(3));
  EXPECT_TRUE(lim.within(start));
  const JointPath path = JointMove::plan(start, arm::Joints(start), lim, 0.5);
  EXPECT_TRUE(lim.within(path.q.front()));
  m.q[3] = lim.q_max(3) + 0.01;
  try {
    move_start_of(m, lim);
    FAIL() << "no error for joint 4 outside its limits";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("joint 4"), std::string::npos) << e.what();
  }
}

TEST(TrajectoryMessage, CarriesEveryPointOfThePath) {
  const arm::JointLimits lim = arm::Puma560::default_limits();
  const arm::Joints from = arm::Joints::Zero();
  arm::Joints to = arm::Joints::Zero();
  to(1) = 0.3;
  const JointPath path = JointMove::plan(from, to, lim, 0.5);
  const joint_trajectory_t m = trajectory_message_of(path, 10, 20);
  EXPECT_EQ(m.utime, 10);
  EXPECT_EQ(m.seq, 20);
  ASSERT_EQ(m.num_points, static_cast<int32_t>(path.t_s.size()));
  ASSERT_EQ(m.q.size(), path.q.size());
  EXPECT_FLOAT_EQ(m.t_s.back(), static_cast<float>(path.duration_s()));
  EXPECT_DOUBLE_EQ(m.q.back()[1], 0.3);
  EXPECT_EQ(m.qd.front().size(), 6u);
}

}  // namespace
}  // namespace ephor::calibrate
