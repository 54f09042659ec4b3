#include "common/display/estop_control.h"

#include <gtest/gtest.h>

namespace ephor::display {
namespace {

TEST(EstopControlTest, StopAndReleaseAreTrueAndFalse) {
  std::string why;
  EXPECT_EQ(EstopControl::parse(std::string("true"), why), std::optional<bool>(true));
  EXPECT_EQ(EstopControl::parse(std::string("0"), why), std::optional<bool>(false));
  EXPECT_TRUE(why.empty());
}

TEST(EstopControlTest, AnythingElseIsRefusedWithAReason) {
  std::string why;
  EXPECT_FALSE(EstopControl::parse(std::string("maybe"), why));
  EXPECT_EQ(why, "estop value 'maybe' is neither true nor false");
  EXPECT_FALSE(EstopControl::parse(std::nullopt, why));
  EXPECT_EQ(why, "estop needs a value");
}

TEST(EstopControlTest, HeldUntilReleased) {
  EstopControl e;
  EXPECT_FALSE(e.held());
  e.set_held(true);
  EXPECT_TRUE(e.held());
  EXPECT_NE(std::string(EstopControl::reason(true)), EstopControl::reason(false));
}

}  // namespace
}  // namespace ephor::display
