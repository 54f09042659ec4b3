#include "procs/stripe/display/stripe_display_feed.h"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "common/fuzz/json_checks.h"

namespace ephor::stripe_display {
namespace {

stripe_scan_t scan(int64_t id, int8_t state) {
  stripe_scan_t m{};
  m.scan_id = id;
  m.state = state;
  m.region_mm[0] = -100.0;
  m.region_mm[1] = -80.0;
  m.region_mm[2] = 100.0;
  m.region_mm[3] = 80.0;
  m.step_mm = 5.0;
  m.height_mm = 400.0;
  m.stripes_planned = 41;
  return m;
}

stripe_points_t points(int64_t scan_id, int n) {
  stripe_points_t m{};
  m.scan_id = scan_id;
  m.num_points = n;
  for (int i = 0; i < n; ++i) {
    m.x_mm.push_back(1.0f * i);
    m.y_mm.push_back(2.0f * i);
    m.z_mm.push_back(20.04f);
  }
  return m;
}

TEST(StripeDisplayFeed, CloudGrowsWithItsScanAndStartsOverWithTheNext) {
  StripeDisplayFeed feed;
  feed.on_points(points(1, 3));  // before any scan: not kept
  feed.on_scan(scan(1, stripe_scan_t::STATE_RUNNING));
  feed.on_points(points(1, 3));
  auto bad = points(1, 2);
  bad.z_mm[1] = std::numeric_limits<float>::quiet_NaN();  // left out
  feed.on_points(bad);
  feed.on_points(points(2, 3));  // another scan's: not kept
  nlohmann::json j = feed.state();
  EXPECT_EQ(j["scan"]["state"], "running");
  EXPECT_EQ(j["cloud"]["points"], 4);
  EXPECT_EQ(j["cloud"]["stripes"], 2);
  const nlohmann::json c = feed.cloud();
  ASSERT_EQ(c["xyz"].size(), 12u);
  EXPECT_EQ(c["xyz"][2].get<double>(), 20.0);  // mm to 0.1

  stripe_cloud_t done{};
  done.scan_id = 1;
  done.path = "scan_1.ply";
  feed.on_cloud(done);
  EXPECT_EQ(feed.state()["cloud"]["path"], "scan_1.ply");
  feed.on_scan(scan(2, stripe_scan_t::STATE_WAITING));
  j = feed.state();
  EXPECT_EQ(j["cloud"]["points"], 0);
  EXPECT_FALSE(j["cloud"]["complete"].get<bool>());
}

// What the fuzz target stripe_display found (issue 18): the scan's region,
// step, height, elapsed time and rate went into the state as they came, so
// a NaN was written as null and the page's toFixed() on it threw. They are
// rounded now, a number that is not finite written as 0.
TEST(StripeDisplayFeed, ScanNumbersThatAreNotFiniteAreWrittenAsZero) {
  StripeDisplayFeed feed;
  stripe_scan_t m = scan(3, stripe_scan_t::STATE_FAILED);
  m.elapsed_s = std::nan("");
  m.stripes_per_s = std::numeric_limits<double>::infinity();
  m.region_mm[2] = std::nan("");
  m.step_mm = 1.7e308;
  m.height_mm = 400.04;
  feed.on_scan(m);
  const nlohmann::json j = feed.state();
  EXPECT_EQ(fuzz::first_non_finite(j), "") << j.dump();
  EXPECT_EQ(j["scan"]["elapsed_s"].get<double>(), 0.0);
  EXPECT_EQ(j["scan"]["stripes_per_s"].get<double>(), 0.0);
  EXPECT_EQ(j["scan"]["region_mm"][2].get<double>(), 0.0);
  EXPECT_EQ(j["scan"]["step_mm"].get<double>(), 1.7e308);
  EXPECT_EQ(j["scan"]["height_mm"].get<double>(), 400.0);
}

}  // namespace
}  // namespace ephor::stripe_display
