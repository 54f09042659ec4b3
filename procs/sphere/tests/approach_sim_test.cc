#include "procs/sphere/tests/approach_sim.h"

#include <gtest/gtest.h>

namespace ephor::sphere {
namespace {

// The whole loop (simulated scans, Scan Line Extent improved, the filter and
// the approach) from 5 m with Table 1's 5 m drift: captured within the
// limits, every window located, no estimate refused by the filter's gate,
// the locator within the paper's 8 mm on every axis and the filter better.
TEST(ApproachSim, CapturesFromFiveMetres) {
  for (uint64_t seed : {1u, 2u}) {
    const ApproachResult r = fly_approach(approach_sim_config(seed, 5.0, 120.0));
    ASSERT_TRUE(r.judged) << "seed " << seed;
    EXPECT_TRUE(r.verdict.captured) << "seed " << seed << ": " << r.verdict.text;
    EXPECT_EQ(r.no_estimates, 0) << "seed " << seed;
    EXPECT_EQ(r.rejected, 0) << "seed " << seed;
    for (int i = 0; i < 3; ++i) {
      EXPECT_LT(r.estimate_rms_m[i], 0.008) << "seed " << seed << " axis " << i;
      EXPECT_LT(r.filter_rms_m[i], r.estimate_rms_m[i]) << "seed " << seed << " axis " << i;
    }
    std::printf("seed %d: %s\n", static_cast<int>(seed), r.verdict.text.c_str());
  }
}

}  // namespace
}  // namespace ephor::sphere
