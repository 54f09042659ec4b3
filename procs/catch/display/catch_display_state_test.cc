#include "procs/catch/display/catch_display_state.h"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "common/fuzz/json_checks.h"

namespace ephor::catch_display {
namespace {

catching::CameraIntrinsics camera() {
  catching::CameraIntrinsics c;
  c.fx = c.fy = 560.0;
  c.cx = 319.5;
  c.cy = 239.5;
  return c;
}

// The board face-on, 2 m out, centred on the optical axis (as in board_projector_test).
BoardPoseView face_on() {
  BoardPoseView p;
  p.valid = true;
  p.r = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  p.t_mm = {-300.0, -450.0, 2000.0};
  p.circles_px = {252.3, 130.3, 386.7, 130.3, 252.3, 348.7, 386.7, 348.7};
  return p;
}

// px of a point of B (pinhole of camera() through face_on()).
std::array<double, 2> px(double x, double y, double z) {
  return {560.0 * (x - 300.0) / (2000.0 + z) + 319.5, 560.0 * (y - 450.0) / (2000.0 + z) + 239.5};
}

void expect_px(const nlohmann::json& j, std::array<double, 2> want) {
  ASSERT_TRUE(j.is_array()) << j.dump();
  EXPECT_NEAR(j[0].get<double>(), want[0], 0.051);  // JSON rounds to 0.1 px
  EXPECT_NEAR(j[1].get<double>(), want[1], 0.051);
}

TEST(CatchDisplayStateTest, BoardOutlineIsTheCornersThroughVisionsPose) {
  CatchDisplayState s({}, camera());
  EXPECT_TRUE(s.to_json(0)["board"].is_null());
  s.on_board_pose(face_on(), 1'000);
  const auto j = s.to_json(2'000);
  const auto& outline = j["board"]["outline"];
  ASSERT_EQ(outline.size(), 4u);
  expect_px(outline[0], {235.5, 113.5});  // top-left of B
  expect_px(outline[1], {403.5, 113.5});  // top-right
  expect_px(outline[2], {403.5, 365.5});  // bottom-right
  expect_px(outline[3], {235.5, 365.5});  // bottom-left
  EXPECT_EQ(j["board"]["bottom_edge"].size(), 2u);
  EXPECT_EQ(j["board"]["circles_px"].size(), 4u);
  EXPECT_FALSE(j["board"]["surveyed"].get<bool>());
}

TEST(CatchDisplayStateTest, NoPoseYetDrawsNoBoard) {
  CatchDisplayState s({}, camera());
  auto p = face_on();
  p.valid = false;
  p.reason = "found 3 of the 4 circles";
  s.on_board_pose(p, 1);
  const auto j = s.to_json(2);
  EXPECT_EQ(j["board"]["reason"], "found 3 of the 4 circles");
  EXPECT_TRUE(j["board"]["outline"].empty());
  EXPECT_TRUE(j["board"]["circles_px"].empty());
}

TEST(CatchDisplayStateTest, PredictedPathEndsAtTheExitPointOnTheBottomEdge) {
  CatchDisplayState s({}, camera());
  s.on_board_pose(face_on(), 0);
  WorldView w;
  w.utime = 10'000'000;
  w.status = 1;
  w.ball_id = 2;
  w.position_b_mm = {200.0, 500.0};
  w.velocity_b_mm_s = {100.0, 300.0};
  w.has_prediction = true;
  // 400 mm to go: at 300 mm/s and a = 200 mm/s^2 the ball takes 1 s; x moves 100 mm.
  w.exit_utime = 11'000'000;
  w.exit_x_b_mm = 300.0;
  w.exit_sigma_mm = 15.0;
  s.on_world(w, 10'000'000);
  const auto j = s.to_json(10'500'000)["world"];
  EXPECT_EQ(j["status"], "tracking");
  EXPECT_NEAR(j["exit_in_s"].get<double>(), 0.5, 1e-9);
  // The ball's centre rolls 20 mm (its radius) above the face.
  expect_px(j["ball_px"], px(200.0, 500.0, 20.0));
  expect_px(j["exit_px"], px(300.0, 900.0, 20.0));
  ASSERT_EQ(j["exit_span_px"].size(), 2u);
  expect_px(j["exit_span_px"][0], px(285.0, 900.0, 20.0));
  expect_px(j["exit_span_px"][1], px(315.0, 900.0, 20.0));
  const auto& path = j["path_px"];
  ASSERT_EQ(path.size(), 17u);  // the start, 15 samples, the exit
  expect_px(path.front(), px(200.0, 500.0, 20.0));
  expect_px(path.back(), px(300.0, 900.0, 20.0));
  // Halfway in time: x = 250, y = 500 + 150 + 25 = 675 mm.
  expect_px(path[8], px(250.0, 675.0, 20.0));
  EXPECT_TRUE(j["catch_px"].is_null());  // the board is not surveyed: W is not in the image
}

TEST(CatchDisplayStateTest, CupAndCatchPointOnceTheBoardIsSurveyed) {
  const catching::BoardSpec board;
  CatchDisplayState s(board, camera());
  s.on_board_pose(face_on(), 0);
  ArmView a;
  a.x_mm = 700;
  a.y_mm = 500;
  a.z_mm = 150;
  s.on_arm(a, 0);
  EXPECT_TRUE(s.to_json(1)["arm"]["cup_px"].is_null());  // W unknown until the survey
  EXPECT_TRUE(s.to_json(1)["arm"]["rim_px"].empty());

  const catching::BoardPlacement placement;  // where the survey will find it
  const auto b2w = catching::board_to_world(board, placement);
  SurveyView survey;
  const double pts[3][2] = {{60, 60}, {540, 60}, {60, 840}};
  for (int i = 0; i < 3; ++i) {
    survey.board_mm[i][0] = pts[i][0];
    survey.board_mm[i][1] = pts[i][1];
    const Eigen::Vector3d w = b2w * Eigen::Vector3d(pts[i][0], pts[i][1], 0.0);
    for (int k = 0; k < 3; ++k) survey.world_mm[i][k] = w[k];
  }
  s.on_survey(survey, 0);
  const auto j = s.to_json(1);
  EXPECT_TRUE(j["board"]["surveyed"].get<bool>());
  EXPECT_NEAR(j["board"]["incline_deg"].get<double>(), 25.0, 0.05);
  // The cup's centre: the tool tip taken from W back to B, then through the pose.
  const Eigen::Vector3d tip_b = b2w.inverse() * Eigen::Vector3d(700, 500, 150);
  expect_px(j["arm"]["cup_px"], px(tip_b.x(), tip_b.y(), tip_b.z()));
  EXPECT_EQ(j["arm"]["rim_px"].size(), 25u);  // closed circle
}

TEST(CatchDisplayStateTest, CatchCountFromTheSimulatorAndBadNumbersDrawNothing) {
  CatchDisplayState s({}, camera());
  TruthView t;
  t.balls_done = 7;
  t.caught = 5;
  t.oracle_reachable = 6;
  t.last_ball = 6;
  t.last_caught = true;
  t.ball_px = {std::nan(""), 3.0};
  s.on_truth(t, 0);
  WorldView w;
  w.position_b_mm = {std::nan(""), std::nan("")};
  w.has_prediction = true;
  w.exit_x_b_mm = std::nan("");
  s.on_world(w, 0);
  BoardPoseView bad = face_on();
  bad.t_mm[2] = std::nan("");
  s.on_board_pose(bad, 0);
  const auto j = s.to_json(1);
  EXPECT_EQ(j["score"]["caught"], 5);
  EXPECT_EQ(j["score"]["balls"], 7);
  EXPECT_EQ(j["score"]["oracle_reachable"], 6);
  EXPECT_TRUE(j["truth"]["ball_px"].is_null());
  EXPECT_FALSE(j["world"].contains("ball_px"));
  EXPECT_FALSE(j["world"].contains("exit_px"));
  EXPECT_TRUE(j["board"]["outline"].empty());
  EXPECT_NO_THROW((void)j.dump());
}

// Seen while writing the fuzz target catch_display (issue 18), as its
// siblings found them: times from the world model more than 2^63 us from
// the wall clock overflowed int64_t (undefined), and a position above
// ~1e307 mm was written as null (r1() overflowed to infinity). The state's
// numbers are finite whatever a message says.
TEST(CatchDisplayStateTest, ExtremeTimesAndPositionsStayFiniteNumbers) {
  CatchDisplayState s({}, camera());
  s.on_board_pose(face_on(), 0);
  WorldView w;
  w.utime = std::numeric_limits<int64_t>::min();
  w.position_b_mm = {1.7e308, -1.7e308};
  w.velocity_b_mm_s = {1e308, 0.0};
  w.has_prediction = true;
  w.exit_x_b_mm = 300.0;
  w.exit_utime = std::numeric_limits<int64_t>::max();
  w.catch_utime = std::numeric_limits<int64_t>::min();
  w.catch_point_w_mm = {1e308, 0.0, 0.0};
  s.on_world(w, 1'700'000'000'000'000);
  const auto j = s.to_json(-1'700'000'000'000'000);
  EXPECT_EQ(fuzz::first_non_finite(j), "") << j.dump();
  EXPECT_EQ(j["world"]["position_b_mm"][0].get<double>(), 1.7e308);
  EXPECT_NEAR(j["world"]["exit_in_s"].get<double>(), 9.2e12, 0.1e12);
  EXPECT_NEAR(j["world"]["catch_in_s"].get<double>(), -9.2e12, 0.1e12);
}

}  // namespace
}  // namespace ephor::catch_display
