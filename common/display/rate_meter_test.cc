#include "common/display/rate_meter.h"

#include <gtest/gtest.h>

namespace ephor::display {
namespace {

TEST(RateMeterTest, CountsPerSecondOverTheWindow) {
  RateMeter m(2.0);
  for (int i = 0; i <= 12; ++i) {
    // BLOBS at 30 Hz, ARM_STATE at 100 Hz, sampled every 0.25 s.
    m.add_sample(i * 0.25, {{"BLOBS", static_cast<uint64_t>(i * 30 / 4)},
                            {"ARM_STATE", static_cast<uint64_t>(i * 25)}});
  }
  const auto r = m.rates();
  EXPECT_NEAR(r.at("BLOBS"), 30.0, 1.0);
  EXPECT_NEAR(r.at("ARM_STATE"), 100.0, 0.1);
}

TEST(RateMeterTest, StoppedChannelFallsToZeroWithinTheWindow) {
  RateMeter m(1.0);
  for (int i = 0; i <= 8; ++i) m.add_sample(i * 0.25, {{"BLOBS", static_cast<uint64_t>(i * 8)}});
  for (int i = 9; i <= 16; ++i) m.add_sample(i * 0.25, {{"BLOBS", 64}});
  EXPECT_EQ(m.rates().at("BLOBS"), 0.0);
}

}  // namespace
}  // namespace ephor::display
