#include "common/lcm/inbox.h"

#include <gtest/gtest.h>

namespace ephor {
namespace {

TEST(Inbox, DrainsInArrivalOrderAndEmpties) {
  Inbox<int> inbox(4);
  EXPECT_TRUE(inbox.push(1));
  EXPECT_TRUE(inbox.push(2));
  EXPECT_TRUE(inbox.push(3));
  EXPECT_EQ(inbox.drain(), (std::vector<int>{1, 2, 3}));
  EXPECT_TRUE(inbox.drain().empty());
  EXPECT_EQ(inbox.dropped(), 0u);
}

TEST(Inbox, WhenFullTheOldestIsDroppedAndCounted) {
  Inbox<int> inbox(2);
  EXPECT_TRUE(inbox.push(1));
  EXPECT_TRUE(inbox.push(2));
  EXPECT_FALSE(inbox.push(3));
  EXPECT_FALSE(inbox.push(4));
  EXPECT_EQ(inbox.dropped(), 2u);
  EXPECT_EQ(inbox.drain(), (std::vector<int>{3, 4}));
}

}  // namespace
}  // namespace ephor
