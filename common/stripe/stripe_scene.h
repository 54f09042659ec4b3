#pragma once
// What the laser meets: a scene's triangles (mm, table frame) over the table
// top z = 0, which is everywhere the scene has no faces (issue 16). Rays are
// cast through a bounding-volume hierarchy (median split on the longest
// axis, up to 4 triangles a leaf).

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "common/stripe/triangle_mesh.h"

namespace ephor::stripe {

struct RayHit {
  double t = 0.0;          // distance along the (unit) ray, mm
  Eigen::Vector3d point;   // mm, table frame
  Eigen::Vector3d normal;  // unit geometric normal, facing the ray's origin
  int face = -1;           // triangle index, -1 for the table top
};

class StripeScene {
 public:
  // An empty table.
  StripeScene();
  explicit StripeScene(TriangleMesh mesh, std::string name = "");
  // Throws SceneFileError naming the file and line.
  static StripeScene load(const std::string& obj_path);

  // First surface along origin + t dir (dir unit) with t_min < t < t_max.
  std::optional<RayHit> first_hit(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir,
                                  double t_min, double t_max) const;
  // Any surface strictly between t_min and t_max (shadow rays).
  bool occluded(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, double t_min,
                double t_max) const;

  // Distance (mm) from p to the nearest point of the scene's surfaces: the
  // triangles and the table top outside the objects' footprint (the true
  // surface for accuracy figures). Brute force over triangles: for
  // benchmarks, not inner loops.
  double distance_to_surface(const Eigen::Vector3d& p) const;

  const TriangleMesh& mesh() const { return mesh_; }
  const std::string& name() const { return name_; }

 private:
  struct Node {
    Eigen::Vector3d lo = Eigen::Vector3d::Zero();
    Eigen::Vector3d hi = Eigen::Vector3d::Zero();
    int left = -1, right = -1;  // children, or -1 for a leaf
    int first = 0, count = 0;   // leaf: triangles order_[first, first + count)
  };
  int build(int first, int count);
  bool hit_mesh(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, double t_min,
                double& t_max, int& face, bool any) const;

  TriangleMesh mesh_;
  std::string name_;
  std::vector<Eigen::Vector3d> tri_lo_, tri_hi_, tri_centre_;
  std::vector<int> order_;
  std::vector<Node> nodes_;
};

}  // namespace ephor::stripe
