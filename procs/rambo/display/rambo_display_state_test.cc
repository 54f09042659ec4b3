#include "procs/rambo/display/rambo_display_state.h"

#include <cmath>
#include <limits>
#include <set>

#include <gtest/gtest.h>

#include "common/fuzz/json_checks.h"
#include "common/rambo/image_triple.h"

namespace ephor::rambo_display {
namespace {

// The target 800 mm in front of a camera at the base's origin, turned so
// the cut corner and three faces are seen.
Eigen::Isometry3d target_pose() {
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.linear() = (Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitX()) *
                Eigen::AngleAxisd(-0.7, Eigen::Vector3d::UnitY()))
                   .toRotationMatrix();
  p.translation() << 20.0, -10.0, 800.0;
  return p;
}

TEST(RamboDisplayState, OutlineEndsAreTheVisibleVerticesProjected) {
  const rambo::RamboCell cell = rambo::RamboCell::make(4);
  const RamboDisplayState s(cell);
  const auto outline = s.outline_px(target_pose(), Eigen::Isometry3d::Identity());
  const auto triples =
      rambo::synthetic_image_triples(cell.model, cell.camera, target_pose(), 0.0, nullptr);
  std::set<std::pair<long, long>> vertices;  // visible vertices' pixels, to 0.1 px
  for (const auto& t : triples)
    vertices.insert({std::lround(t.reference_px.x() * 10), std::lround(t.reference_px.y() * 10)});
  ASSERT_GE(outline.size(), 6u);
  for (const auto& e : outline) {
    EXPECT_TRUE(vertices.count({std::lround(e[0] * 10), std::lround(e[1] * 10)}))
        << e[0] << ", " << e[1];
    EXPECT_TRUE(vertices.count({std::lround(e[2] * 10), std::lround(e[3] * 10)}))
        << e[2] << ", " << e[3];
  }
}

TEST(RamboDisplayState, StateCarriesImagePosesOrderAndTaggedDiodes) {
  RamboDisplayState s(rambo::RamboCell::make(4));
  const nlohmann::json empty = s.state();
  EXPECT_TRUE(empty["pose"]["estimated"].is_null());
  EXPECT_TRUE(empty["plan"].is_null());
  ASSERT_EQ(empty["diodes"].size(), 4u);
  EXPECT_FALSE(empty["diodes"][0]["tagged"].get<bool>());

  TruthView truth;
  truth.utime = 1000;
  truth.frame_index = 7;
  truth.target_in_base = target_pose();
  truth.carrier_mm = {{1400, 0, -340}, {1400, 0, -90}, {1290, 0, 100},
                      {1130, 0, 100},  {1030, 0, 100}, {830, 0, 100}};  // the RM-501's chain
  s.on_truth(truth);
  FeaturesView f;
  f.frame_index = 7;
  f.source = "features";
  f.corners_px = {{100, 100}, {200, 100}, {150, 180}};
  f.edges = {{0, 1}, {1, 2}};
  f.triples = 1;
  s.on_features(f);
  PoseView p;
  p.utime = 1000;
  p.frame_index = 7;
  p.found = true;
  p.target_in_base = target_pose();
  p.target_in_base.translation().x() += 3.0;  // 3 mm off the truth
  p.matched_triangles_px = {{100, 100, 200, 100, 150, 180}};
  s.on_pose(p);
  PlanView plan;
  plan.order = {2, 0, 3};
  plan.current_task = 2;
  plan.dp_trajectories = 15;
  s.on_plan(plan);
  IndicatorView ind;
  ind.tagged = {false, true, false, false};
  ind.tagged_utime = {0, 5e6, 0, 0};
  ind.lit_diode = 2;
  ind.beam_angle_deg = {10, 20, 3, 40};
  ind.beam_offset_mm = {1, 2, 3, 4};
  s.on_indicator(ind);

  const nlohmann::json j = s.state();
  EXPECT_EQ(j["image"]["features"]["corners"].size(), 3u);
  EXPECT_EQ(j["image"]["features"]["edges"].size(), 2u);
  EXPECT_EQ(j["image"]["matched_triangles"].size(), 1u);
  EXPECT_GE(j["image"]["estimated_outline"].size(), 6u);
  EXPECT_NEAR(j["pose"]["estimated"]["error_mm"].get<double>(), 3.0, 1e-6);
  EXPECT_NEAR(j["pose"]["estimated"]["error_deg"].get<double>(), 0.0, 1e-6);
  EXPECT_NEAR(j["pose"]["true"]["t_mm"][2].get<double>(), 800.0, 1e-9);
  ASSERT_EQ(j["pose"]["true"]["carrier_mm"].size(), 6u);
  EXPECT_NEAR(j["pose"]["true"]["carrier_mm"][2][0].get<double>(), 1290.0, 1e-9);
  EXPECT_NEAR(j["pose"]["estimated"]["t_mm"][0].get<double>(), 23.0, 1e-9);
  const rambo::RamboCell cell = rambo::RamboCell::make(4);
  ASSERT_EQ(j["plan"]["order"].size(), 3u);
  EXPECT_EQ(j["plan"]["order"][0]["name"], cell.diodes[2].name);
  EXPECT_EQ(j["plan"]["current"]["diode"], 2);
  EXPECT_EQ(j["plan"]["trajectories"]["dynamic_programming"], 15);
  EXPECT_TRUE(j["diodes"][1]["tagged"].get<bool>());
  EXPECT_FALSE(j["diodes"][0]["tagged"].get<bool>());
  EXPECT_TRUE(j["diodes"][2]["lit"].get<bool>());
  EXPECT_EQ(j["indicator"]["tagged"], 1);

  const nlohmann::json m = s.model();
  EXPECT_EQ(m["vertices"].size(), cell.model.vertices().size());
  EXPECT_EQ(m["faces"].size(), cell.model.faces().size());
  EXPECT_EQ(m["diodes"].size(), 4u);
}

// What the fuzz target rambo_display found (issue 18): a rotation above
// ~1e303 was written as null (rounded() overflowed to infinity). Seen beside
// it: the indicator's required_s and acceptance_deg went out raw (NaN as
// null), and a tagged time that is NaN or beyond int64_t was converted to
// int64_t (undefined). Every number is finite; a tagged time that is not one
// is null.
TEST(RamboDisplayState, CorruptMessagesLeaveFiniteNumbers) {
  RamboDisplayState s(rambo::RamboCell::make(4));
  TruthView t;
  t.target_in_base.translation() << 1.7e308, 0.0, 800.0;
  t.camera_in_base.linear()(1, 1) = 1e306;
  s.on_truth(t);
  IndicatorView i;
  i.tagged = {true, true, true, false};
  i.tagged_utime = {std::nan(""), 1e30, 1.7e15, 0.0};
  i.required_s = std::nan("");
  i.acceptance_deg = std::numeric_limits<double>::infinity();
  s.on_indicator(i);
  const nlohmann::json j = s.state();
  EXPECT_EQ(fuzz::first_non_finite(j), "") << j.dump();
  EXPECT_EQ(j["pose"]["true"]["t_mm"][0].get<double>(), 1.7e308);
  EXPECT_TRUE(j["diodes"][0]["tagged_utime"].is_null());
  EXPECT_TRUE(j["diodes"][1]["tagged_utime"].is_null());
  EXPECT_EQ(j["diodes"][2]["tagged_utime"].get<int64_t>(), 1'700'000'000'000'000);
  EXPECT_EQ(j["indicator"]["required_s"].get<double>(), 0.0);
}

}  // namespace
}  // namespace ephor::rambo_display
