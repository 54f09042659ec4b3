#pragma once
// The target's geometric model (RAMBO paper, sections 3-5, 7): a convex
// polyhedron's vertices and faces in the target frame (mm), the edges and
// "model triangles" (a vertex with two vertices joined to it by edges) that
// pose estimation matches image triangles against, and the goal points
// (tool poses fixed in the target frame) of the tasks.

#include <array>
#include <string>
#include <vector>

#include <Eigen/Geometry>

namespace ephor::rambo {

struct GoalPoint {
  std::string name;
  // Tool pose in the target frame, mm: for laser tagging, a point on the
  // diode's optical axis at the standoff, z axis (the beam) pointing at it.
  Eigen::Isometry3d in_target = Eigen::Isometry3d::Identity();
};

// A reference vertex and the two vertices joined to it (a < b).
struct ModelTriangle {
  int reference = -1;
  int a = -1;
  int b = -1;
};

class TargetModel {
 public:
  // Throws std::invalid_argument with a one-line reason: fewer than 4
  // vertices, a non-finite vertex, a face with fewer than 3 vertices or one
  // that names a missing vertex, or a goal point farther than
  // max_goal_standoff_mm from the target's bounding sphere.
  TargetModel(std::vector<Eigen::Vector3d> vertices_mm, std::vector<std::vector<int>> faces,
              std::vector<GoalPoint> goals = {}, double max_goal_standoff_mm = 1000.0);

  const std::vector<Eigen::Vector3d>& vertices() const { return vertices_; }
  const std::vector<std::vector<int>>& faces() const { return faces_; }
  const std::vector<GoalPoint>& goals() const { return goals_; }
  const std::vector<std::array<int, 2>>& edges() const { return edges_; }
  const std::vector<ModelTriangle>& triangles() const { return triangles_; }
  const std::vector<std::vector<int>>& neighbours() const { return neighbours_; }
  // Vertex centroid (target frame, mm) and the radius about it.
  const Eigen::Vector3d& centre() const { return centre_; }
  double bounding_radius_mm() const { return radius_; }
  // Outward unit normal of face f (away from the centre: convex model).
  const Eigen::Vector3d& face_normal(int f) const { return normals_[static_cast<std::size_t>(f)]; }

  // The largest signed distance of p (target frame, mm) from the face planes,
  // > 0 outside: for a convex model 0 on the surface, minus the depth inside,
  // and outside at most the distance to the surface (equal when a face is
  // nearest). `face` (optional) gets the plane that gives it.
  double surface_distance_mm(const Eigen::Vector3d& p, int* face = nullptr) const;

  // Vertices on faces that face a camera at `camera_in_target` (mm).
  std::vector<bool> visible_vertices(const Eigen::Vector3d& camera_in_target) const;
  // Edges on at least one face that faces the camera.
  std::vector<bool> visible_edges(const Eigen::Vector3d& camera_in_target) const;

  // A box (sx x sy x sz mm, centred) with its (+x, +y, +z) corner cut off
  // by a plane through the points cut_mm along each edge from the corner:
  // 10 vertices, 7 planar faces, and no rotational symmetry to confuse pose.
  static TargetModel truncated_box(double sx_mm, double sy_mm, double sz_mm,
                                   const Eigen::Vector3d& cut_mm);

 private:
  std::vector<Eigen::Vector3d> vertices_;
  std::vector<std::vector<int>> faces_;
  std::vector<GoalPoint> goals_;
  std::vector<std::array<int, 2>> edges_;
  std::vector<std::vector<int>> neighbours_;
  std::vector<ModelTriangle> triangles_;
  std::vector<Eigen::Vector3d> normals_;
  std::vector<std::vector<int>> edge_faces_;
  Eigen::Vector3d centre_ = Eigen::Vector3d::Zero();
  double radius_ = 0.0;
};

}  // namespace ephor::rambo
