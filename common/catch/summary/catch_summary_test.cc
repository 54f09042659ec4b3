#include "common/catch/summary/catch_summary.h"

#include <limits>

#include <gtest/gtest.h>

#include "common/log/json_text.h"

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

// Strings in the summary come off the bus (a task's name, a miss's reason) and
// may be any bytes: the summary is still written (json_text), where nlohmann's
// dump() threw and ephor-catch-monitor lost the whole summary at exit.
TEST(CatchSummary, IsWrittenWhateverBytesTheStringsCarry) {
  CatchSummary s(7);
  s.on_truth(4000, false, {0, 0}, 0, false, true, "cup \xff\xfe far",
             Eigen::Isometry3d::Identity());
  s.on_task("vision\xc3", "blobify", 900, 1500, 10, 0);
  EXPECT_THROW((void)s.to_json().dump(), nlohmann::json::type_error);
  const std::string text = json_text(s.to_json(), 2);
  EXPECT_NE(text.find("cup \xef\xbf\xbd\xef\xbf\xbd far"), std::string::npos);  // U+FFFD twice
}

// Deadline misses are summed over hosts from the wire: a corrupt count must
// not overflow the sum (undefined behaviour) or make it negative.
TEST(CatchSummary, DeadlineMissesFromTheWireSaturate) {
  CatchSummary s(7);
  s.on_sched_status("a", true, std::numeric_limits<int64_t>::max());
  s.on_sched_status("b", true, 5);
  s.on_sched_status("c", true, -7);
  EXPECT_EQ(s.to_json()["deadline_misses"], std::numeric_limits<int64_t>::max());
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

TEST(ClassifyMiss, NamesTheLossFromThePredictionsAgainstTheTrueExit) {
  BallTrack t;
  t.true_exit_x_b_mm = 300.0;
  t.true_exit_utime = 2'000'000;
  BallOutcome o;
  classify_miss(t, 30.0, 0.5, o);
  EXPECT_EQ(o.kind, "not tracked");

  t.first_tracked_y_mm = 120.0;
  t.predictions = {{1'000'000, 100.0}, {1'500'000, 250.0}, {1'900'000, 200.0}};
  o = {};
  classify_miss(t, 30.0, 0.5, o);
  EXPECT_EQ(o.kind, "wrong place");
  EXPECT_NEAR(o.prediction_error_mm, 100.0, 1e-9);
  EXPECT_NEAR(o.first_tracked_y_mm, 120.0, 1e-9);

  // Within 30 mm from 1.7 s on (the 1.5 s one is 50 mm off): 0.3 s ahead.
  t.predictions = {{1'000'000, 310.0}, {1'500'000, 250.0}, {1'700'000, 320.0}, {1'900'000, 295.0}};
  o = {};
  classify_miss(t, 30.0, 0.5, o);
  EXPECT_EQ(o.kind, "prediction late");
  EXPECT_NEAR(o.lead_s, 0.3, 1e-9);
  EXPECT_NEAR(o.prediction_error_mm, 5.0, 1e-9);

  // Settled 1 s ahead: the arm had the time.
  t.predictions = {{1'000'000, 310.0}, {1'500'000, 290.0}, {1'900'000, 295.0}};
  o = {};
  classify_miss(t, 30.0, 0.5, o);
  EXPECT_EQ(o.kind, "arm late");
  EXPECT_NEAR(o.lead_s, 1.0, 1e-9);
}

TEST(CatchSummary, ClassifiesAMissedBallFromTheWorldModelsPredictions) {
  CatchSummary s(3);
  const Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  // Ball 0 rolls in two frames; the world model predicts its exit in both,
  // the second time 10 mm off, 0.9 s before the true exit: the arm was late.
  for (int64_t u : {1'000'000, 1'100'000}) {
    s.on_truth(u, true, {300, 100}, -1, false, false, "", pose);
    s.on_ball_truth(u, 0, true, {300.0, 100.0}, 300.0, 2'000'000);
  }
  s.on_prediction(1'000'000, true, true, 400.0, Eigen::Vector2d(300.0, 110.0));
  s.on_prediction(1'100'000, true, true, 310.0, Eigen::Vector2d(300.0, 160.0));
  s.on_prediction(1'200'000, true, true, 0.0);  // no truth frame: ignored
  s.on_truth(2'500'000, false, {0, 0}, 0, false, true, "cup 90 mm from the ball's path", pose);
  const auto j = s.to_json();
  ASSERT_EQ(j["missed"].size(), 1u);
  EXPECT_EQ(j["missed"][0]["kind"], "arm late");
  EXPECT_NEAR(j["missed"][0]["lead_s"].get<double>(), 0.9, 1e-9);
  EXPECT_NEAR(j["missed"][0]["first_tracked_y_mm"].get<double>(), 100.0, 1e-9);
  EXPECT_NEAR(j["missed"][0]["max_track_error_mm"].get<double>(), 60.0, 1e-9);
  EXPECT_NEAR(j["missed"][0]["strayed_at_y_mm"].get<double>(), 100.0, 1e-9);
  EXPECT_EQ(j["missed_kinds"]["arm late"], 1);
  EXPECT_EQ(j["missed_kinds_oracle_reachable"]["arm late"], 1);
}

}  // namespace
}  // namespace ephor::catching
