// The scan planner's pure parts: the raster plan and its checks (a region
// out of reach names its corner), and the sequence of goals and captures.

#include <gtest/gtest.h>

#include "common/stripe/scan_geometry.h"
#include "procs/stripe/planner/raster_plan.h"
#include "procs/stripe/planner/scan_sequencer.h"

namespace ephor::stripe {
namespace {

geometry::Workcell stripe_cell() {
  geometry::Workcell w;
  w.field_length_mm = 1100;
  w.field_width_mm = 1000;
  w.base_x_mm = 0;
  w.base_y_mm = 500;
  w.base_z_mm = 450;
  w.tool_length_mm = 100;
  return w;
}

TEST(RasterPlan, PlansTheDefaultSquareAtTheWorkingHeight) {
  RasterSpec spec;
  parse_region("-200,-200,200,200", spec);
  const RasterPlan plan =
      plan_raster(spec, stripe_cell(), TrueArm::nominal(), SensorCalibration::drawing_cage());
  // 41 stripes 10 mm apart in each of 4 passes of 100 mm.
  EXPECT_EQ(plan.goals.size(), 4u * 41u);
  EXPECT_EQ(plan.goals.size(), plan.projector_poses.size());
  // Neighbouring stripes are small moves of the same configuration.
  for (size_t i = 1; i < 41; ++i)
    EXPECT_LT((plan.goals[i] - plan.goals[i - 1]).cwiseAbs().maxCoeff(), 0.1) << i;
}

TEST(RasterPlan, AnOutOfReachRegionNamesItsCorner) {
  RasterSpec spec;
  parse_region("-100,-100,100,900", spec);
  try {
    plan_raster(spec, stripe_cell(), TrueArm::nominal(), SensorCalibration::drawing_cage());
    FAIL() << "planned a region 900 mm out";
  } catch (const PlanError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind("region corner (x0, y1) = (-100, 900) mm is out of reach", 0), 0u) << what;
  }
  // Under the shoulder: the corner near the column.
  parse_region("-600,-50,0,50", spec);
  try {
    plan_raster(spec, stripe_cell(), TrueArm::nominal(), SensorCalibration::drawing_cage());
    FAIL() << "planned a region over the column";
  } catch (const PlanError& e) {
    EXPECT_NE(std::string(e.what()).find("region corner (x0, y0) = (-600, -50) mm"),
              std::string::npos)
        << e.what();
  }
}

TEST(RasterPlan, BadRegionsAndStepsAreRefused) {
  RasterSpec spec;
  EXPECT_THROW(parse_region("1,2,3", spec), PlanError);
  EXPECT_THROW(parse_region("1,2,3,x", spec), PlanError);
  EXPECT_THROW(parse_region("10,0,0,10", spec), PlanError);
  EXPECT_THROW(parse_region("0,0,nan,10", spec), PlanError);
  parse_region("0,0,10,10", spec);
  spec.step_mm = 0;
  EXPECT_THROW(
      plan_raster(spec, stripe_cell(), TrueArm::nominal(), SensorCalibration::drawing_cage()),
      PlanError);
}

std::vector<arm::Joints> three() {
  return {arm::Joints::Constant(0.1), arm::Joints::Constant(0.2), arm::Joints::Constant(0.3)};
}

TEST(ScanSequencer, ProbeThenGoalCaptureGoalUntilTheCloud) {
  ScanSequencer s(three(), 10, 100);
  EXPECT_EQ(s.state(), ScanState::kWaiting);
  auto a = s.start(0.0);
  ASSERT_TRUE(a.capture);
  EXPECT_EQ(a.capture->stripe, -1);
  EXPECT_EQ(a.capture->request_id, 100);
  EXPECT_FALSE(s.on_image(100, 7, 0.1).goal);  // the probe's image: its points next
  EXPECT_FALSE(s.on_points(6, 0.2).goal);      // another image's points
  a = s.on_points(7, 0.2);
  ASSERT_TRUE(a.goal);
  EXPECT_EQ(s.state(), ScanState::kRunning);
  EXPECT_EQ(a.goal->goal_id, 10);
  EXPECT_EQ(a.goal->stripe, 0);
  double t = 0.2;
  for (int i = 0; i < 3; ++i) {
    EXPECT_FALSE(s.on_motion_done(999, 0, "", t).capture);  // not ours
    a = s.on_motion_done(10 + i, 0, "", t += 0.3);
    ASSERT_TRUE(a.capture) << i;
    EXPECT_EQ(a.capture->stripe, i);
    a = s.on_image(a.capture->request_id, 8 + i, t += 0.01);
    EXPECT_TRUE(a.changed);
    if (i < 2) {
      ASSERT_TRUE(a.goal) << "the next goal goes out with the image (overlap)";
      EXPECT_EQ(a.goal->stripe, i + 1);
    }
    if (i < 2) s.on_ranged(i, i + 1, t);
  }
  EXPECT_EQ(s.state(), ScanState::kRunning) << "the last stripe's points not heard yet";
  EXPECT_FALSE(s.on_ranged(2, 3, t).goal);
  EXPECT_EQ(s.state(), ScanState::kCaptured);
  EXPECT_EQ(s.retaken(), 0);
  EXPECT_EQ(s.captured(), 3);
  EXPECT_NEAR(s.stripes_per_s(), 2.0 / 0.62, 1e-9);
  EXPECT_NEAR(s.motion_s(), 0.9, 1e-9);
  s.on_cloud(1234, t + 0.1);
  EXPECT_EQ(s.state(), ScanState::kDone);
  EXPECT_EQ(s.cloud_points(), 1234);
  EXPECT_EQ(s.next_goal_id(), 13);
}

TEST(ScanSequencer, RefusedGoalsSkipFailedOnesAreTriedAgainThenFail) {
  SequencerConfig c;
  c.goal_attempts = 2;
  ScanSequencer s(three(), 1, 1, c);
  s.start(0);
  s.on_image(1, 0, 0);
  auto a = s.on_points(0, 0);
  a = s.on_motion_done(a.goal->goal_id, 1, "collides", 1);
  ASSERT_TRUE(a.goal);
  EXPECT_EQ(a.goal->stripe, 1);
  EXPECT_EQ(s.skipped(), 1);
  a = s.on_motion_done(a.goal->goal_id, 2, "servo fault", 2);
  ASSERT_TRUE(a.goal) << "a failed move is tried again";
  EXPECT_EQ(a.goal->stripe, 1);
  a = s.on_motion_done(a.goal->goal_id, 2, "servo fault", 3);
  EXPECT_EQ(s.state(), ScanState::kFailed);
  EXPECT_NE(s.reason().find("servo fault"), std::string::npos);
}

TEST(ScanSequencer, LostCapturesAreAskedAgainThenFail) {
  SequencerConfig c;
  c.capture_attempts = 3;
  ScanSequencer s(three(), 1, 1, c);
  auto a = s.start(0);
  EXPECT_FALSE(s.tick(0.5).capture);
  a = s.tick(1.01);
  ASSERT_TRUE(a.capture);
  EXPECT_EQ(a.capture->request_id, 1) << "a repeat keeps its id";
  s.tick(2.02);
  a = s.tick(3.03);
  EXPECT_EQ(s.state(), ScanState::kFailed);
  EXPECT_NE(s.reason().find("probe"), std::string::npos) << s.reason();
}

TEST(ScanSequencer, NoCloudFailsAfterItsTimeout) {
  ScanSequencer s({arm::Joints::Zero()}, 1, 1);
  s.start(0);
  s.on_image(1, 0, 0);
  auto a = s.on_points(0, 0);
  a = s.on_motion_done(a.goal->goal_id, 0, "", 1);
  s.on_image(a.capture->request_id, 1, 1.1);
  s.on_ranged(0, 1, 1.2);
  EXPECT_EQ(s.state(), ScanState::kCaptured);
  s.tick(10);
  EXPECT_EQ(s.state(), ScanState::kCaptured);
  s.tick(30);
  EXPECT_EQ(s.state(), ScanState::kFailed);
}

// Takes the stripe of `goal` to its image: MOTION_DONE, capture, image.
SequencerActions image_stripe(ScanSequencer& s, const GoalAction& goal, double t) {
  const SequencerActions a = s.on_motion_done(goal.goal_id, 0, "", t);
  EXPECT_TRUE(a.capture);
  return s.on_image(a.capture->request_id, 100 + goal.stripe, t + 0.01);
}

SequencerActions start_scan(ScanSequencer& s) {
  s.start(0);
  s.on_image(1, 0, 0);
  return s.on_points(0, 0);
}

// Issue 18: an image whose points never come (the stripe process killed
// while it had it, a packet lost) is taken again after the raster, under a
// new goal id, and the scan then completes.
TEST(ScanSequencer, AStripeWithoutPointsIsTakenAgainAfterTheRaster) {
  ScanSequencer s(three(), 1, 1);
  auto a = start_scan(s);
  a = image_stripe(s, *a.goal, 1);
  s.on_ranged(0, 1, 1.1);
  a = image_stripe(s, *a.goal, 2);  // stripe 1: its points lost
  a = image_stripe(s, *a.goal, 3);
  EXPECT_FALSE(a.goal) << "the raster is done";
  s.on_ranged(2, 2, 3.1);
  EXPECT_EQ(s.state(), ScanState::kRunning);
  EXPECT_FALSE(s.tick(4.0).goal) << "waits ranged_timeout_s for late points";
  a = s.tick(5.1);
  ASSERT_TRUE(a.goal);
  EXPECT_EQ(a.goal->stripe, 1);
  EXPECT_EQ(a.goal->goal_id, 4) << "a new goal id, never the old one's";
  EXPECT_EQ(s.retaken(), 1);
  image_stripe(s, *a.goal, 6);
  s.on_ranged(1, 3, 6.1);
  EXPECT_EQ(s.state(), ScanState::kCaptured);
  EXPECT_EQ(s.captured(), 3);
}

// The range process restarted mid-scan: it says it holds 1 stripe after 2
// were ranged, so the stripes before are taken again.
TEST(ScanSequencer, ARestartedRangeProcessGetsItsLostStripesAgain) {
  ScanSequencer s(three(), 1, 1);
  auto a = start_scan(s);
  a = image_stripe(s, *a.goal, 1);
  s.on_ranged(0, 1, 1.1);
  a = image_stripe(s, *a.goal, 2);
  s.on_ranged(1, 2, 2.1);
  a = image_stripe(s, *a.goal, 3);
  s.on_ranged(2, 1, 3.1);  // the new range process: only stripe 2
  EXPECT_EQ(s.range_losses(), 1);
  EXPECT_EQ(s.ranged(), 1);
  a = s.tick(5.2);
  ASSERT_TRUE(a.goal);
  EXPECT_EQ(a.goal->stripe, 0);
  a = image_stripe(s, *a.goal, 6);
  ASSERT_TRUE(a.goal);
  EXPECT_EQ(a.goal->stripe, 1);
  s.on_ranged(0, 2, 6.1);
  image_stripe(s, *a.goal, 7);
  s.on_ranged(1, 3, 7.1);
  EXPECT_EQ(s.state(), ScanState::kCaptured);
  EXPECT_EQ(s.retaken(), 2);
}

// A goal that comm timed out, or whose MOTION_DONE never came (comm or the
// arm restarted), goes again under a new id, goal_attempts times in all.
TEST(ScanSequencer, UnansweredGoalsAreSentAgainUnderNewIdsThenFail) {
  SequencerConfig c;
  c.motion_timeout_s = 10.0;
  c.goal_attempts = 3;
  ScanSequencer s(three(), 1, 1, c);
  auto a = start_scan(s);
  ASSERT_TRUE(a.goal);
  const int64_t first = a.goal->goal_id;
  a = s.on_motion_done(first, 3, "no answer from the arm", 1);
  ASSERT_TRUE(a.goal);
  EXPECT_EQ(a.goal->stripe, 0);
  EXPECT_EQ(a.goal->goal_id, first + 1);
  EXPECT_FALSE(s.on_motion_done(first, 0, "", 1.5).capture) << "the old goal's late answer";
  EXPECT_FALSE(s.tick(10.5).goal);
  s.on_arm_moving(10.6);  // a long move under way: not overdue
  EXPECT_FALSE(s.tick(20.0).goal);
  a = s.tick(20.7);
  ASSERT_TRUE(a.goal);
  EXPECT_EQ(a.goal->goal_id, first + 2);
  s.tick(30.8);
  EXPECT_EQ(s.state(), ScanState::kFailed);
  EXPECT_NE(s.reason().find("3 goals sent"), std::string::npos) << s.reason();
}

// A refused stripe is asked for once more in the next round, then left.
TEST(ScanSequencer, ARefusedStripeIsAskedAgainOnceThenSkipped) {
  SequencerConfig c;
  c.retake_rounds = 1;
  ScanSequencer s({arm::Joints::Zero(), arm::Joints::Zero()}, 1, 1, c);
  auto a = start_scan(s);
  a = s.on_motion_done(a.goal->goal_id, 1, "collides", 1);
  ASSERT_TRUE(a.goal);
  EXPECT_EQ(a.goal->stripe, 1);
  image_stripe(s, *a.goal, 2);
  a = s.on_ranged(1, 1, 2.1);
  ASSERT_TRUE(a.goal) << "no image waits for its points: the refused stripe at once";
  EXPECT_EQ(a.goal->stripe, 0);
  s.on_motion_done(a.goal->goal_id, 1, "collides", 3);
  EXPECT_EQ(s.state(), ScanState::kCaptured);
  EXPECT_EQ(s.skipped(), 1);
  EXPECT_EQ(s.captured(), 1);
}

}  // namespace
}  // namespace ephor::stripe
