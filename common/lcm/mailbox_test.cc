#include "common/lcm/mailbox.h"

#include <thread>

#include <gtest/gtest.h>

namespace ephor {
namespace {

TEST(Mailbox, EmptyTakeReturnsNothing) {
  Mailbox<int> box;
  EXPECT_FALSE(box.take().has_value());
  EXPECT_FALSE(box.latest().has_value());
  EXPECT_EQ(box.received(), 0u);
}

TEST(Mailbox, KeepsOnlyTheNewestAndCountsOverwrites) {
  Mailbox<int> box;
  box.put(1);
  box.put(2);
  box.put(3);
  EXPECT_EQ(box.take(), 3);
  EXPECT_EQ(box.received(), 3u);
  EXPECT_EQ(box.overwritten(), 2u);
  // Taken: a second take finds nothing new, but latest() still has it.
  EXPECT_FALSE(box.take().has_value());
  EXPECT_EQ(box.latest(), 3);
}

TEST(Mailbox, WaitTakeTimesOutWithoutMessage) {
  Mailbox<int> box;
  EXPECT_FALSE(box.wait_take(std::chrono::milliseconds(5)).has_value());
}

TEST(Mailbox, WaitTakeWakesOnPutFromAnotherThread) {
  Mailbox<int> box;
  std::thread writer([&] { box.put(42); });
  auto got = box.wait_take(std::chrono::seconds(5));
  writer.join();
  ASSERT_TRUE(got.has_value());
  EXPECT_EQ(*got, 42);
}

}  // namespace
}  // namespace ephor
