#include "common/display/json_format.h"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

namespace ephor::display {
namespace {

TEST(JsonFormat, RoundsToTheDigitsAsked) {
  EXPECT_DOUBLE_EQ(r1(1.26), 1.3);
  EXPECT_DOUBLE_EQ(rounded(0.12345, 3), 0.123);
  EXPECT_DOUBLE_EQ(rounded(-2.5, 0), -3.0);
}

TEST(JsonFormat, NotFiniteIsZero) {
  EXPECT_EQ(r1(std::nan("")), 0.0);
  EXPECT_EQ(rounded(std::numeric_limits<double>::infinity(), 2), 0.0);
  EXPECT_EQ(rounded(-std::numeric_limits<double>::infinity(), 2), 0.0);
}

// Found by the rambo_display and sphere_display fuzz targets: a huge finite
// value (a rotation or an elevation from a corrupt message) times 10^digits
// overflowed to infinity, which nlohmann writes as null. Such a value is a
// whole number already: it is kept as it is.
TEST(JsonFormat, HugeFiniteValueIsKept) {
  EXPECT_EQ(rounded(1e306, 5), 1e306);
  EXPECT_EQ(r1(-1.7e308), -1.7e308);
}

}  // namespace
}  // namespace ephor::display
