#include "procs/catch/monitor/catch_summary.h"

#include <gtest/gtest.h>

namespace ephor::catching {
namespace {

TEST(CatchSummary, CountsEachBallOnceWithItsReason) {
  CatchSummary s(7);
  const Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  s.on_truth(1000, true, {10, 20}, -1, false, false, "", pose);
  s.on_truth(2000, false, {0, 0}, 0, true, true, "caught: cup 4 mm from the ball's path", pose);
  s.on_truth(3000, false, {0, 0}, 0, true, true, "caught: cup 4 mm from the ball's path", pose);
  s.on_truth(4000, false, {0, 0}, 1, false, true, "cup 43 mm from the ball's path", pose);
  const auto j = s.to_json();
  EXPECT_EQ(j["balls"], 2);
  EXPECT_EQ(j["caught"], 1);
  EXPECT_EQ(j["oracle_reachable"], 2);
  ASSERT_EQ(j["missed"].size(), 1u);
  EXPECT_EQ(j["missed"][0]["reason"], "cup 43 mm from the ball's path");
}

TEST(CatchSummary, ScoresWorldOutputsAgainstTheTruthOfTheirFrame) {
  CatchSummary s(1);
  const Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  s.on_truth(1'000'000, true, {100, 200}, -1, false, false, "", pose);
  s.on_truth(1'016'667, true, {100, 210}, -1, false, false, "", pose);
  s.on_world(1'000'000, 1.5, Eigen::Vector2d(103, 204));
  s.on_world(1'016'667, 2.5, Eigen::Vector2d(100, 210));
  const auto j = s.to_json();
  EXPECT_NEAR(j["position_error_mm"]["max"].get<double>(), 5.0, 1e-9);
  EXPECT_NEAR(j["update_ms"]["p50"].get<double>(), 16.667, 1e-9);
  EXPECT_NEAR(j["throughput_ms"]["max"].get<double>(), 2.5, 1e-9);
}

}  // namespace
}  // namespace ephor::catching
