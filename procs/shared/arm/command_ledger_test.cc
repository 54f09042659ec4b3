// CommandLedger: each command executed at most once, also across a restart
// of the arm (issue 18 item 4: "the arm executes no goal twice").
#include "procs/shared/arm/command_ledger.h"

#include <cstdint>
#include <limits>

#include <gtest/gtest.h>

namespace ephor::arm {
namespace {

constexpr int64_t kStart = 1'700'000'000'000'000;  // wall clock of the arm's start, us

TEST(CommandLedgerTest, RemembersTheNewestAckPerCommandAndForgetsTheOldest) {
  CommandLedger ledger(0, 2);
  ArmAck a;
  a.seq = 1;
  a.status = AckStatus::kAccepted;
  ledger.record(1, 100, a);
  a.status = AckStatus::kDone;
  ledger.record(1, 100, a);
  ASSERT_TRUE(ledger.find(1, 100));
  EXPECT_EQ(ledger.find(1, 100)->status, AckStatus::kDone);
  EXPECT_FALSE(ledger.find(1, 999));  // same seq from a restarted sender: a new command
  ledger.record(2, 200, a);
  ledger.record(3, 300, a);
  EXPECT_FALSE(ledger.find(1, 100));
  EXPECT_TRUE(ledger.find(3, 300));
  EXPECT_EQ(ledger.size(), 2u);
}

TEST(CommandLedgerTest, VouchesOnlyForCommandsFirstSentSinceItBegan) {
  const CommandLedger ledger(kStart);
  EXPECT_FALSE(ledger.refusal(7, kStart));
  EXPECT_FALSE(ledger.refusal(7, kStart + 1));
  const auto why = ledger.refusal(7, kStart - 150'000);
  ASSERT_TRUE(why);
  EXPECT_NE(why->find("seq 7"), std::string::npos) << *why;
  EXPECT_NE(why->find("0.150 s before this arm started"), std::string::npos) << *why;
  // A corrupt send time is refused too, without overflowing the difference.
  EXPECT_TRUE(ledger.refusal(7, std::numeric_limits<int64_t>::min()));
}

// The fault tests' case: the arm was executing seq 12 when it was killed;
// comm polls seq 12 (same first-sent utime) and the restarted arm gets it.
// The killed run's ledger died with it: the new one has never seen seq 12,
// and must not take it as new.
TEST(CommandLedgerTest, ARestartedArmDoesNotExecuteTheKilledRunsCommandAgain) {
  const int64_t sent = kStart - 300'000;  // first sent 0.3 s before the restart
  CommandLedger killed(kStart - 10'000'000);
  EXPECT_FALSE(killed.refusal(12, sent));  // the first run took it
  ArmAck accepted;
  accepted.seq = 12;
  accepted.status = AckStatus::kAccepted;
  killed.record(12, sent, accepted);

  const CommandLedger restarted(kStart);
  EXPECT_FALSE(restarted.find(12, sent));
  EXPECT_TRUE(restarted.refusal(12, sent));
  // comm's next goal, first sent after the restart, is executed.
  EXPECT_FALSE(restarted.refusal(13, kStart + 200'000));
}

}  // namespace
}  // namespace ephor::arm
