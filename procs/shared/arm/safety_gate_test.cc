#include "procs/shared/arm/safety_gate.h"

#include <gtest/gtest.h>

namespace ephor::arm {
namespace {

TEST(SafetyGateTest, EstopLatchesUntilReleased) {
  SafetyGate gate;
  gate.on_comm_heard(0);
  EXPECT_FALSE(gate.refuse_command());
  EXPECT_TRUE(gate.on_estop(true, "display", "operator pressed stop"));
  EXPECT_FALSE(gate.on_estop(true, "display", "again"));  // repeated stop: no change
  ASSERT_TRUE(gate.refuse_command());
  EXPECT_NE(gate.refuse_command()->find("operator pressed stop"), std::string::npos);
  EXPECT_NE(gate.refuse_command()->find("'display'"), std::string::npos);
  // Stops a motion, whatever comm does.
  gate.on_comm_heard(10);
  EXPECT_TRUE(gate.stop_reason(true, 20));
  EXPECT_FALSE(gate.stop_reason(false, 20));  // nothing moving: nothing to stop
  EXPECT_TRUE(gate.on_estop(false, "display", ""));
  EXPECT_FALSE(gate.refuse_command());
  EXPECT_FALSE(gate.stop_reason(true, 20));
}

TEST(SafetyGateTest, SilentCommStopsARunningMotionOnly) {
  SafetyGate gate({.comm_timeout_us = 1'000'000});
  gate.on_comm_heard(5'000'000);
  EXPECT_FALSE(gate.stop_reason(true, 5'900'000));
  gate.on_comm_heard(5'900'000);  // a poll
  EXPECT_FALSE(gate.stop_reason(true, 6'800'000));
  const auto why = gate.stop_reason(true, 7'000'001);
  ASSERT_TRUE(why);
  EXPECT_NE(why->find("comm"), std::string::npos);
  EXPECT_FALSE(gate.stop_reason(false, 60'000'000));  // idle arm: comm may be quiet
  EXPECT_FALSE(gate.refuse_command());                // and may send again
}

TEST(SafetyGateTest, WatchdogOffWithZeroTimeout) {
  SafetyGate gate({.comm_timeout_us = 0});
  EXPECT_FALSE(gate.stop_reason(true, 1'000'000'000));
}

}  // namespace
}  // namespace ephor::arm
