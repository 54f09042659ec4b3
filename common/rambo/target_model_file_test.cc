// The target model file (deploy/rambo/target.pbtxt) against the built-in
// target, its eight diodes' goal points at rest, and one refusal per kind of
// bad input, each naming what is wrong and where.
#include "common/rambo/target_model_file.h"

#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "common/config/repo_paths.h"
#include "common/config/text_proto.h"
#include "common/rambo/diode_indicator.h"

namespace ephor::rambo {
namespace {

std::string deploy_model_path() { return (repo_dir() / "deploy/rambo/target.pbtxt").string(); }

// A unit tetrahedron-like body (mm) with one diode on its z = 0 face.
constexpr const char* kTetra = R"(
vertex { x: 0 y: 0 z: 0 }
vertex { x: 100 y: 0 z: 0 }
vertex { x: 0 y: 100 z: 0 }
vertex { x: 0 y: 0 z: 100 }
face { vertex: [0, 2, 1] }
face { vertex: [0, 1, 3] }
face { vertex: [0, 3, 2] }
face { vertex: [1, 2, 3] }
principal_moments_mm2 { x: 1 y: 1 z: 1 }
diode { name: "under" lens_mm { x: 20 y: 20 z: 0 } axis { x: 0 y: 0 z: -1 } }
)";

// The ConfigError's message for `text`, or "" when it loads.
std::string refusal(const std::string& text) {
  try {
    parse_target_model(text, "model.pbtxt");
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

TEST(TargetModelFile, DeployFileIsTheBuiltInTargetWithFourMoreDiodes) {
  const TargetSpec file = load_target_model_file(deploy_model_path());
  const TargetSpec code = RamboCell::builtin_target();
  ASSERT_EQ(file.vertices_mm.size(), code.vertices_mm.size());
  for (std::size_t i = 0; i < code.vertices_mm.size(); ++i)
    EXPECT_TRUE(file.vertices_mm[i].isApprox(code.vertices_mm[i])) << "vertex " << i;
  EXPECT_EQ(file.faces, code.faces);
  EXPECT_TRUE(file.principal_moments_mm2.isApprox(code.principal_moments_mm2));
  ASSERT_EQ(file.diodes.size(), 8u);
  for (std::size_t i = 0; i < code.diodes.size(); ++i) {
    EXPECT_EQ(file.diodes[i].name, code.diodes[i].name);
    EXPECT_TRUE(file.diodes[i].lens_mm.isApprox(code.diodes[i].lens_mm)) << i;
    EXPECT_TRUE(file.diodes[i].axis.isApprox(code.diodes[i].axis)) << i;
    EXPECT_DOUBLE_EQ(file.diodes[i].standoff_mm, code.diodes[i].standoff_mm);
  }
}

TEST(TargetModelFile, EveryDiodesGoalLightsItAndIsReachableAtRest) {
  const TargetSpec spec = load_target_model_file(deploy_model_path());
  const RamboCell cell = RamboCell::make(spec, 8);
  const arm::Puma560 arm(cell.tool_length_mm);
  TumblingMotion m = cell.draw_motion(1, 2.0, 1.0);
  m.pose0.linear().setIdentity();
  DiodeIndicator ind(cell.diodes, RamboCell::kAcceptanceDeg, RamboCell::kLensRadiusMm, 1.0);
  const Eigen::Isometry3d start = arm.forward(cell.start_joints);
  for (int i = 0; i < 8; ++i) {
    const Eigen::Isometry3d goal = m.pose0 * cell.goal_in_target(i);
    EXPECT_TRUE(arm.nearest_inverse(goal, cell.start_joints).has_value()) << cell.diodes[i].name;
    const DiodeReading r = ind.read(i, m.pose0, goal.translation(), goal.linear().col(2));
    EXPECT_TRUE(r.lit) << cell.diodes[i].name;
    EXPECT_FALSE(ind.read(i, m.pose0, start.translation(), start.linear().col(2)).lit)
        << cell.diodes[i].name << " lit from the start pose";
  }
  EXPECT_THROW(RamboCell::make(spec, 9), std::invalid_argument);
  EXPECT_THROW(RamboCell::make(spec, 0), std::invalid_argument);
}

TEST(TargetModelFile, TheHandModelLoads) {
  const TargetSpec t = parse_target_model(kTetra, "tetra");
  EXPECT_EQ(t.vertices_mm.size(), 4u);
  ASSERT_EQ(t.diodes.size(), 1u);
  EXPECT_DOUBLE_EQ(t.diodes[0].standoff_mm, RamboCell::kStandoffMm);
}

TEST(TargetModelFile, AFaceNamingAMissingVertexIsRefusedByFaceAndIndex) {
  const std::string e =
      refusal(replaced(kTetra, "face { vertex: [1, 2, 3] }", "face { vertex: [1, 2, 7] }"));
  EXPECT_NE(e.find("model.pbtxt:9: face[3]:"), std::string::npos) << e;
  EXPECT_NE(e.find("face 3 index 2 names vertex 7, which is missing (vertices are 0-3)"),
            std::string::npos)
      << e;
}

TEST(TargetModelFile, AGoalPointOffTheTargetIsRefusedByNameAndDistance) {
  std::string e =
      refusal(replaced(kTetra, "lens_mm { x: 20 y: 20 z: 0 }", "lens_mm { x: 20 y: 20 z: -35 }"));
  EXPECT_NE(e.find("diode[0].lens_mm: goal point diode[0] ('under') is off the target: its lens is "
                   "35 mm outside the surface"),
            std::string::npos)
      << e;
  e = refusal(replaced(kTetra, "lens_mm { x: 20 y: 20 z: 0 }", "lens_mm { x: 20 y: 20 z: 10 }"));
  EXPECT_NE(e.find("its lens is 10 mm inside the surface"), std::string::npos) << e;
  e = refusal(replaced(kTetra, "axis { x: 0 y: 0 z: -1 }", "axis { x: 0 y: 0 z: 1 }"));
  EXPECT_NE(e.find("the axis does not point out of face 0"), std::string::npos) << e;
}

TEST(TargetModelFile, NaNIsRefusedWithItsField) {
  std::string e =
      refusal(replaced(kTetra, "vertex { x: 0 y: 100 z: 0 }", "vertex { x: nan y: 100 z: 0 }"));
  EXPECT_NE(e.find("model.pbtxt:4: vertex[2]: is not finite (nan, 100, 0)"), std::string::npos)
      << e;
  e = refusal(replaced(kTetra, "axis { x: 0 y: 0 z: -1 }", "axis { x: 0 y: inf z: -1 }"));
  EXPECT_NE(e.find("diode[0].axis: is not finite"), std::string::npos) << e;
}

TEST(TargetModelFile, FewerThanFourVerticesIsRefused) {
  const std::string e = refusal(replaced(kTetra, "vertex { x: 0 y: 0 z: 100 }", ""));
  EXPECT_NE(e.find("vertex: the model has 3 vertices, a polyhedron needs at least 4"),
            std::string::npos)
      << e;
}

TEST(TargetModelFile, OtherBadModelsSayWhatIsWrong) {
  // Not convex (faces 0, 1, 2 no longer planar): the box's vertex 0 moved up.
  std::ifstream in(deploy_model_path());
  std::stringstream box;
  box << in.rdbuf();
  const std::string e = refusal(
      replaced(box.str(), "vertex { x: 120 y: 90 z: -70 }", "vertex { x: 120 y: 90 z: -30 }"));
  EXPECT_NE(e.find("mm outside face 0's plane: the model must be convex with planar faces"),
            std::string::npos)
      << e;
  // A repeated vertex in a face (TargetModel's own check).
  EXPECT_NE(refusal(replaced(kTetra, "face { vertex: [1, 2, 3] }", "face { vertex: [1, 1, 3] }"))
                .find("repeats vertex 1"),
            std::string::npos);
  EXPECT_NE(refusal(replaced(kTetra, "principal_moments_mm2 { x: 1 y: 1 z: 1 }", ""))
                .find("principal_moments_mm2: missing"),
            std::string::npos);
  EXPECT_NE(
      refusal(std::string(kTetra) + "goal_standoff_mm: -3\n").find("goal_standoff_mm: must be"),
      std::string::npos);
  EXPECT_NE(refusal(std::string(kTetra) + "bogus: 1\n").find("bogus"), std::string::npos);
  std::string nine = kTetra;
  for (int i = 0; i < 8; ++i)
    nine += "diode { name: \"d" + std::to_string(i) +
            "\" lens_mm { x: 20 y: 20 z: 0 } axis { x: 0 y: 0 z: -1 } }\n";
  EXPECT_NE(refusal(nine).find("the model has 9 diodes, at most 8"), std::string::npos);
  try {
    load_target_model_file("/nonexistent/target.pbtxt");
    ADD_FAILURE() << "a missing file loaded";
  } catch (const ConfigError& err) {
    EXPECT_NE(std::string(err.what()).find("cannot open file"), std::string::npos);
  }
}

}  // namespace
}  // namespace ephor::rambo
