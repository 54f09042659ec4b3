#include "procs/rambo/sim/sim_messages.h"

#include <cstdint>
#include <string>

#include <gtest/gtest.h>

#include "common/arm/arm_workcell.h"
#include "common/geometry/message_pose.h"
#include "common/geometry/workcell.h"
#include "common/log/json_text.h"
#include "common/rambo/target_model_file.h"

namespace ephor::rambo {
namespace {

constexpr int64_t kWall0Us = 1'700'000'000'000'000;

struct Sim {
  RamboCell cell = cell_from_flags("", 4);
  SimWorld w{cell, cell.draw_motion(1, 2.0, 1.0), arm::make_puma(geometry::Workcell{}).limits()};
  Sim() { w.wall0_us = kWall0Us; }
};

TEST(SimWorldTest, ABadTrajectoryIsRefusedAndCounted) {
  Sim s;
  joint_trajectory_t m{};
  m.seq = 3;
  m.num_points = 0;
  s.w.on_trajectory(m);
  EXPECT_EQ(s.w.refused.load(), 1);
  EXPECT_FALSE(s.w.pending.has_value());
}

TEST(SimWorldTest, APoseOfAFrameIsScoredAgainstItsTruth) {
  Sim s;
  const CameraShot shot = s.w.camera_shot(0.2);
  rambo_pose_t m{};
  m.utime = shot.truth.utime;
  m.found = true;
  Eigen::Isometry3d est = shot.target;
  est.translation().x() += 3.0;
  geometry::set_pose(est, m.target_r, m.target_t_mm);
  m.pose_ms = 4.0;
  s.w.on_pose(m);
  EXPECT_EQ(s.w.poses_found, 1);
  ASSERT_EQ(s.w.pose_err_mm.size(), 1u);
  EXPECT_NEAR(s.w.pose_err_mm[0], 3.0, 1e-9);
  EXPECT_NEAR(s.w.pose_err_deg[0], 0.0, 1e-6);
}

// Found by the fuzz target rambo_sim: a RAMBO_POSE's features_source (or a
// scheduler's host or task name) that is not UTF-8 made nlohmann's dump()
// throw at exit, and the run's summary was lost. It is written with U+FFFD.
TEST(SimWorldTest, TheSummaryIsWrittenWhateverBytesTheBusSent) {
  Sim s;
  rambo_pose_t pose{};
  pose.features_source = "\xff\xfe oracle";
  s.w.on_pose(pose);
  sched_status_t status{};
  status.host = "host\x91";
  task_status_t task{};
  task.process = "sim\xc3";
  task.task = "physics";
  status.tasks.push_back(task);
  status.num_tasks = 1;
  s.w.on_sched_status(status);
  const nlohmann::json summary = s.w.summary(1, 2.0);
  EXPECT_THROW((void)summary.dump(), nlohmann::json::type_error);  // why json_text
  std::string text;
  ASSERT_NO_THROW(text = json_text(summary, 2));
  EXPECT_NE(text.find("\xEF\xBF\xBD oracle"), std::string::npos);
  EXPECT_EQ(nlohmann::json::parse(text)["poses"], 1);
}

rambo_prediction_t fitted_prediction(int64_t ref_utime) {
  rambo_prediction_t m{};
  m.fitted = true;
  m.model = "rigid-body";
  m.ref_utime = ref_utime;
  m.samples = 10;
  m.position_mm[0] = 900.0;
  m.orientation_wxyz[0] = 1.0;
  m.principal_moments[0] = 1.0;
  m.principal_moments[1] = 1.2;
  m.principal_moments[2] = 1.5;
  return m;
}

// Found by the fuzz target rambo_sim: a fitted RAMBO_PREDICTION whose
// numbers are finite but whose predicted points are not (or are too large
// to measure a distance to): its errors scored NaN in the summary. Now a
// bad message.
TEST(SimWorldTest, APredictionThatCannotBeScoredIsABadMessage) {
  Sim s;
  rambo_prediction_t m = fitted_prediction(kWall0Us);
  m.velocity_mm_s[0] = 1e300;
  s.w.on_prediction(m);
  EXPECT_EQ(s.w.bad_messages, 1);
  EXPECT_EQ(s.w.predictions, 0);
  EXPECT_TRUE(s.w.pending_predictions.empty());
  s.w.on_prediction(fitted_prediction(kWall0Us));
  EXPECT_EQ(s.w.predictions, 1);
  EXPECT_EQ(s.w.pending_predictions.size(), 3u);
}

// The same for a pose, read while fixing the above: a "rotation" of huge
// numbers scored a NaN angle.
TEST(SimWorldTest, APoseThatCannotBeScoredIsABadMessage) {
  Sim s;
  const CameraShot shot = s.w.camera_shot(0.2);
  rambo_pose_t m{};
  m.utime = shot.truth.utime;
  m.found = true;
  geometry::set_pose(shot.target, m.target_r, m.target_t_mm);
  for (double& r : m.target_r) r = 1.7e308;  // finite; R^T R_truth overflows
  s.w.on_pose(m);
  EXPECT_EQ(s.w.bad_messages, 1);
  EXPECT_EQ(s.w.poses_found, 0);
  EXPECT_TRUE(s.w.pose_err_deg.empty());
}

// Read while fixing the above (signed overflow, undefined behaviour): a
// prediction's ref_utime far from the run's clock, and deadline-miss counts
// that sum past INT64_MAX (they saturate, as the monitors' do).
TEST(SimWorldTest, ExtremeTimesAndCountsDoNotOverflow) {
  Sim s;
  EXPECT_LT(s.w.t_of(INT64_MIN), -1e12);
  EXPECT_GT(s.w.t_of(INT64_MAX), 1e12);
  s.w.on_prediction(fitted_prediction(INT64_MIN));
  EXPECT_EQ(s.w.predictions, 1);
  sched_status_t status{};
  status.host = "a";
  task_status_t task{};
  task.deadline_misses = INT64_MAX;
  status.tasks = {task, task};
  status.num_tasks = 2;
  s.w.on_sched_status(status);
  status.host = "b";
  s.w.on_sched_status(status);
  EXPECT_EQ(s.w.summary(1, 2.0)["deadline_misses"], INT64_MAX);
}

}  // namespace
}  // namespace ephor::rambo
