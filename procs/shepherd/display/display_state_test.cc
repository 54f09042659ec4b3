#include "procs/shepherd/display/display_state.h"

#include <cmath>

#include <gtest/gtest.h>

#include "common/geometry/overhead_camera.h"
#include "common/geometry/workcell.h"

namespace ephor::display {
namespace {

DisplayState make_state() {
  const geometry::Workcell cell;
  const auto cal = calibration::FieldCalibration::from_camera(geometry::OverheadCamera{}, cell);
  return DisplayState(
      OverlayGeometry(cal.matrix_at_height(0.0), cell.field_length_mm, cell.field_width_mm),
      DisplayOptions{});
}

TEST(DisplayStateTest, OneCirclePerBlobAndObscuredObjectsMarked) {
  auto s = make_state();
  BlobsView b;
  b.frame_index = 9;
  b.mode = 1;
  b.blobs = {{100, 100, 150}, {200, 120, 80}};
  s.on_blobs(b, 1'000'000);
  s.on_objects(
      {{1, 0, 100, 100, 10, 0, 0, 150}, {2, 1, 300, 300, 0, 5, 0.4, 90}, {3, 2, 0, 0, 0, 0, 9, 0}},
      1'000'000);
  const auto j = s.to_json(Controls{}, 1'050'000);
  EXPECT_EQ(s.circle_count(), 2u);
  ASSERT_EQ(j["blobs"]["circles"].size(), 2u);
  EXPECT_EQ(j["blobs"]["mode"], "trackify");
  EXPECT_NEAR(j["blobs"]["age_ms"].get<double>(), 50.0, 1e-9);
  ASSERT_EQ(j["objects"].size(), 2u);  // the dead one is not drawn
  EXPECT_EQ(j["objects"][1]["state"], "obscured");
  // Path: 3 s ahead at 10 px/s.
  EXPECT_NEAR(j["objects"][0]["path"].back()[0].get<double>(), 130.0, 1e-9);
  EXPECT_EQ(j["boundary"].size(), 4u);
}

TEST(DisplayStateTest, ScoreCountsSheepOnTheField) {
  auto s = make_state();
  TruthView t;
  t.sheep = {{1, 10, 10, true, true}, {2, 20, 20, false, true}, {3, 30, 30, true, false}};
  t.saves = 4;
  t.escapes = 1;
  t.sim_time_s = 12.3;
  s.on_truth(t, 5);
  const auto j = s.to_json(Controls{}, 10);
  EXPECT_EQ(j["truth"]["on_field"], 2);
  EXPECT_EQ(j["truth"]["visible"], 1);
  EXPECT_EQ(j["truth"]["saves"], 4);
  EXPECT_EQ(j["truth"]["escapes"], 1);
}

TEST(DisplayStateTest, LatencyIgnoresResends) {
  auto s = make_state();
  s.on_arm_command("comm", 1, 1'000'000, 1'040'000);
  s.on_arm_command("comm", 1, 1'000'000, 1'900'000);  // resend of seq 1
  s.on_arm_command("comm", 2, 2'000'000, 2'060'000);
  const auto j = s.to_json(Controls{}, 0);
  EXPECT_EQ(j["latency"]["commands"], 2);
  EXPECT_NEAR(j["latency"]["max_ms"].get<double>(), 60.0, 1e-9);
}

// Found by the shepherd_display fuzz target: an ARM_STATE with a NaN angle
// went into the page's state as null (JSON has no NaN), which the page's
// drawing of the tool then read as 0 without saying so. Every number the page
// draws is finite: a value that is not is shown as 0.
TEST(DisplayStateTest, ArmAngleThatIsNotFiniteIsZero) {
  auto s = make_state();
  s.on_arm({100.0, 120.0, std::nan(""), 50.0, true, 80.0}, 1'000'000);
  const auto j = s.to_json(Controls{}, 1'000'000);
  ASSERT_TRUE(j["arm"]["theta_rad"].is_number());
  EXPECT_EQ(j["arm"]["theta_rad"].get<double>(), 0.0);
}

TEST(DisplayStateTest, NothingHeardYetIsNull) {
  const auto j = make_state().to_json(Controls{}, 0);
  EXPECT_TRUE(j["blobs"].is_null());
  EXPECT_TRUE(j["planner"].is_null());
  EXPECT_TRUE(j["arm"].is_null());
  EXPECT_TRUE(j["truth"].is_null());
  EXPECT_EQ(j["controls"]["mode"], "blobify");
}

}  // namespace
}  // namespace ephor::display
