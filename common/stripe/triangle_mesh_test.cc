#include "common/stripe/triangle_mesh.h"

#include <gtest/gtest.h>

#include "common/stripe/stripe_scene.h"

namespace ephor::stripe {
namespace {

std::string error_of(const std::string& text) {
  try {
    parse_obj(text, "t.obj");
  } catch (const SceneFileError& e) {
    return e.what();
  }
  return "";
}

TEST(TriangleMeshTest, ParsesPolygonsAndIndexForms) {
  const TriangleMesh m = parse_obj(
      "# a quad and a triangle\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\n"
      "f 1//1 2//1 3//1 4//1\nf -1 -2 -3\n",
      "t.obj");
  ASSERT_EQ(m.vertices.size(), 4u);
  ASSERT_EQ(m.faces.size(), 3u);
  EXPECT_EQ(m.faces[1], Eigen::Vector3i(0, 2, 3));
  EXPECT_EQ(m.faces[2], Eigen::Vector3i(3, 2, 1));
  const TriangleMesh back = parse_obj(to_obj(m, "round trip"), "back.obj");
  EXPECT_EQ(back.faces.size(), 3u);
}

TEST(TriangleMeshTest, BadFilesNameTheLineAndProblem) {
  EXPECT_EQ(error_of("v 0 0 0\nv 1 2\n"),
            "scene file t.obj line 2: vertex needs 3 coordinates (x y z [w]), got 2");
  EXPECT_EQ(error_of("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n"),
            "scene file t.obj line 4: face index 9 out of range (3 vertices so far)");
  EXPECT_EQ(error_of("v 0 0 x\n"), "scene file t.obj line 1: 'x' is not a number");
  EXPECT_EQ(error_of("v 0 0 nan\n"), "scene file t.obj line 1: coordinate 'nan' is not finite");
  EXPECT_EQ(error_of("v 0 0 0\nbanana 1\n"),
            "scene file t.obj line 2: unknown OBJ statement 'banana'");
  EXPECT_EQ(error_of("v 0 0 0\nv 1 0 0\nf 1 2\n"),
            "scene file t.obj line 3: face needs at least 3 vertices, got 2");
  EXPECT_EQ(error_of("v 0 0 0\n"), "scene file t.obj: no faces");
  EXPECT_THROW(load_obj("/nonexistent/scene.obj"), SceneFileError);
}

TEST(TriangleMeshTest, TheThreeScenesLoad) {
  const std::string dir = EPHOR_STRIPE_SCENES;
  const TriangleMesh plate = load_obj(dir + "/flat_plate.obj");
  EXPECT_EQ(plate.faces.size(), 12u);
  EXPECT_DOUBLE_EQ(plate.max_corner().z(), 20.0);
  const TriangleMesh pyramid = load_obj(dir + "/pyramid.obj");
  EXPECT_DOUBLE_EQ(pyramid.max_corner().z(), 60.0);
  const TriangleMesh cup = load_obj(dir + "/cup_spoon.obj");
  EXPECT_GT(cup.faces.size(), 500u);
  EXPECT_NEAR(cup.max_corner().z(), 95.0, 1e-9);
  EXPECT_GE(cup.min_corner().z(), 0.0);
}

TEST(StripeSceneTest, RaysMeetObjectsAndTheTable) {
  const StripeScene scene = StripeScene::load(std::string(EPHOR_STRIPE_SCENES) + "/pyramid.obj");
  const Eigen::Vector3d down(0, 0, -1);
  auto apex = scene.first_hit(Eigen::Vector3d(0, 0, 300), down, 0.0, 1e4);
  ASSERT_TRUE(apex.has_value());
  EXPECT_NEAR(apex->t, 240.0, 1e-9);
  // On a face at 45 deg: 30 mm out from the apex along x the face is 30 mm lower.
  auto face = scene.first_hit(Eigen::Vector3d(30, 0, 300), down, 0.0, 1e4);
  ASSERT_TRUE(face.has_value());
  EXPECT_NEAR(face->point.z(), 30.0, 1e-9);
  EXPECT_NEAR(face->normal.dot(Eigen::Vector3d(1, 0, 1).normalized()), 1.0, 1e-9);
  auto table = scene.first_hit(Eigen::Vector3d(100, 0, 300), down, 0.0, 1e4);
  ASSERT_TRUE(table.has_value());
  EXPECT_EQ(table->face, -1);
  EXPECT_NEAR(table->point.z(), 0.0, 1e-12);
  // Distances to the true surface.
  EXPECT_NEAR(scene.distance_to_surface(Eigen::Vector3d(0, 0, 61)), 1.0, 1e-9);
  EXPECT_NEAR(scene.distance_to_surface(Eigen::Vector3d(150, 0, 2)), 2.0, 1e-9);
}

}  // namespace
}  // namespace ephor::stripe
