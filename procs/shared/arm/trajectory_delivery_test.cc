#include "procs/shared/arm/trajectory_delivery.h"

#include <gtest/gtest.h>

namespace ephor::arm {
namespace {

using Action = TrajectoryDelivery::Action;
constexpr int64_t kT0 = 1'000'000'000;  // us
constexpr int64_t kMs = 1000;

ServoState following(int64_t seq, const Joints& q = Joints::Zero()) {
  ServoState s;
  s.q = q;
  s.trajectory_seq = seq;
  return s;
}

TEST(TrajectoryDeliveryTest, ATrajectoryTakenUpIsNotSentAgain) {
  TrajectoryDelivery d;
  d.sent(5, Joints::Zero(), false, kT0);
  EXPECT_EQ(d.check(following(4), kT0 + 5 * kMs), Action::kNone);  // not due yet
  EXPECT_EQ(d.check(following(5), kT0 + 8 * kMs), Action::kNone);
  EXPECT_FALSE(d.pending());
  EXPECT_EQ(d.check(following(4), kT0 + 500 * kMs), Action::kNone);  // no longer watched
  EXPECT_EQ(d.resends(), 0);
}

TEST(TrajectoryDeliveryTest, ALostMotionIsSentAgainWhileTheArmIsAtItsStart) {
  TrajectoryDelivery d;
  const Joints start = Joints::Constant(0.3);
  d.sent(5, start, false, kT0);
  EXPECT_EQ(d.check(following(4, start), kT0 + 99 * kMs), Action::kNone);
  EXPECT_EQ(d.check(following(4, start), kT0 + 101 * kMs), Action::kResend);
  d.resent(kT0 + 101 * kMs);
  EXPECT_EQ(d.check(following(4, start), kT0 + 150 * kMs), Action::kNone);  // waits again
  EXPECT_EQ(d.check(following(4, start), kT0 + 202 * kMs), Action::kResend);
  d.resent(kT0 + 202 * kMs);
  EXPECT_EQ(d.resends(), 2);
  EXPECT_EQ(d.check(following(5, start), kT0 + 210 * kMs), Action::kNone);
  EXPECT_FALSE(d.pending());
}

TEST(TrajectoryDeliveryTest, ALostMotionIsGivenUpOnceTheArmHasMovedFromItsStart) {
  TrajectoryDelivery d;
  const Joints start = Joints::Constant(0.3);
  Joints moved = start;
  moved(2) += 0.05;  // still following the motion before
  d.sent(9, start, false, kT0);
  EXPECT_EQ(d.check(following(8, moved), kT0 + 120 * kMs), Action::kGiveUp);
  EXPECT_NE(d.why().find("trajectory 9 was not taken up"), std::string::npos) << d.why();
  EXPECT_NE(d.why().find("joint 3"), std::string::npos) << d.why();
  EXPECT_FALSE(d.pending());
  EXPECT_EQ(d.check(following(8, moved), kT0 + 300 * kMs), Action::kNone);
}

TEST(TrajectoryDeliveryTest, ALostStopIsPlannedAgainFromWhereTheArmIs) {
  TrajectoryDelivery d;
  d.sent(11, Joints::Zero(), true, kT0);
  // The arm keeps moving on its old motion: a stop is never given up.
  EXPECT_EQ(d.check(following(10, Joints::Constant(0.2)), kT0 + 150 * kMs), Action::kReplanStop);
  d.sent(12, Joints::Constant(0.2), true, kT0 + 150 * kMs);
  EXPECT_EQ(d.check(following(12, Joints::Constant(0.21)), kT0 + 160 * kMs), Action::kNone);
  EXPECT_FALSE(d.pending());
}

}  // namespace
}  // namespace ephor::arm
