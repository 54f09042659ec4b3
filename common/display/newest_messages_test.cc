#include "common/display/newest_messages.h"

#include <gtest/gtest.h>

namespace ephor::display {
namespace {

struct Reading {
  int value = 0;
};
void to_json(nlohmann::json& j, const Reading& r) { j = {{"value", r.value}}; }

TEST(NewestMessagesTest, KeepsOnlyTheNewestPerKey) {
  NewestMessages n;
  n.put("A", Reading{1});
  n.put("A", Reading{2});
  n.put("B/host", Reading{7});
  const auto j = n.to_json();
  EXPECT_EQ(j.size(), 2u);
  EXPECT_EQ(j["A"]["value"], 2);
  EXPECT_EQ(j["B/host"]["value"], 7);
}

TEST(NewestMessagesTest, NothingHeardIsAnEmptyObject) {
  const auto j = NewestMessages{}.to_json();
  EXPECT_TRUE(j.is_object());
  EXPECT_TRUE(j.empty());
}

}  // namespace
}  // namespace ephor::display
