#include "common/rambo/target_model.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>

namespace ephor::rambo {

TargetModel::TargetModel(std::vector<Eigen::Vector3d> vertices_mm,
                         std::vector<std::vector<int>> faces, std::vector<GoalPoint> goals,
                         double max_goal_standoff_mm)
    : vertices_(std::move(vertices_mm)), faces_(std::move(faces)), goals_(std::move(goals)) {
  const int nv = static_cast<int>(vertices_.size());
  if (nv < 4) throw std::invalid_argument("target model: needs at least 4 vertices");
  for (int i = 0; i < nv; ++i) {
    if (!vertices_[static_cast<std::size_t>(i)].allFinite())
      throw std::invalid_argument("target model: vertex " + std::to_string(i) + " is not finite");
    centre_ += vertices_[static_cast<std::size_t>(i)] / nv;
  }
  for (const auto& v : vertices_) radius_ = std::max(radius_, (v - centre_).norm());
  std::map<std::array<int, 2>, std::vector<int>> edge_faces;
  for (std::size_t f = 0; f < faces_.size(); ++f) {
    const auto& face = faces_[f];
    if (face.size() < 3)
      throw std::invalid_argument("target model: face " + std::to_string(f) +
                                  " has fewer than 3 vertices");
    for (int v : face) {
      if (v < 0 || v >= nv)
        throw std::invalid_argument("target model: face " + std::to_string(f) +
                                    " names missing vertex " + std::to_string(v) + " (model has " +
                                    std::to_string(nv) + ")");
    }
    Eigen::Vector3d n = Eigen::Vector3d::Zero(), c = Eigen::Vector3d::Zero();
    for (std::size_t k = 0; k < face.size(); ++k) {
      const auto& p = vertices_[static_cast<std::size_t>(face[k])];
      const auto& q = vertices_[static_cast<std::size_t>(face[(k + 1) % face.size()])];
      n += p.cross(q);  // Newell's normal
      c += p / static_cast<double>(face.size());
      std::array<int, 2> e{std::min(face[k], face[(k + 1) % face.size()]),
                           std::max(face[k], face[(k + 1) % face.size()])};
      if (e[0] == e[1])
        throw std::invalid_argument("target model: face " + std::to_string(f) + " repeats vertex " +
                                    std::to_string(e[0]));
      edge_faces[e].push_back(static_cast<int>(f));
    }
    if (n.norm() < 1e-9)
      throw std::invalid_argument("target model: face " + std::to_string(f) + " has no area");
    n.normalize();
    if (n.dot(c - centre_) < 0.0) n = -n;
    normals_.push_back(n);
  }
  neighbours_.resize(static_cast<std::size_t>(nv));
  for (const auto& [e, fs] : edge_faces) {
    edges_.push_back(e);
    edge_faces_.push_back(fs);
    neighbours_[static_cast<std::size_t>(e[0])].push_back(e[1]);
    neighbours_[static_cast<std::size_t>(e[1])].push_back(e[0]);
  }
  for (int v = 0; v < nv; ++v) {
    auto& nb = neighbours_[static_cast<std::size_t>(v)];
    std::sort(nb.begin(), nb.end());
    for (std::size_t i = 0; i < nb.size(); ++i)
      for (std::size_t j = i + 1; j < nb.size(); ++j) triangles_.push_back({v, nb[i], nb[j]});
  }
  for (const auto& g : goals_) {
    if (!g.in_target.matrix().allFinite())
      throw std::invalid_argument("target model: goal point '" + g.name + "' is not finite");
    const double d = (g.in_target.translation() - centre_).norm() - radius_;
    if (d > max_goal_standoff_mm) {
      std::ostringstream o;
      o << "target model: goal point '" << g.name << "' is " << d
        << " mm off the target (more than " << max_goal_standoff_mm << " mm)";
      throw std::invalid_argument(o.str());
    }
  }
}

double TargetModel::surface_distance_mm(const Eigen::Vector3d& p, int* face) const {
  double best = -std::numeric_limits<double>::infinity();
  for (std::size_t f = 0; f < faces_.size(); ++f) {
    const double d = normals_[f].dot(p - vertices_[static_cast<std::size_t>(faces_[f][0])]);
    if (d > best) {
      best = d;
      if (face != nullptr) *face = static_cast<int>(f);
    }
  }
  return best;
}

std::vector<bool> TargetModel::visible_vertices(const Eigen::Vector3d& camera_in_target) const {
  std::vector<bool> vis(vertices_.size(), false);
  for (std::size_t f = 0; f < faces_.size(); ++f) {
    const auto& p = vertices_[static_cast<std::size_t>(faces_[f][0])];
    if (normals_[f].dot(camera_in_target - p) <= 0.0) continue;
    for (int v : faces_[f]) vis[static_cast<std::size_t>(v)] = true;
  }
  return vis;
}

std::vector<bool> TargetModel::visible_edges(const Eigen::Vector3d& camera_in_target) const {
  std::vector<bool> facing(faces_.size(), false);
  for (std::size_t f = 0; f < faces_.size(); ++f) {
    const auto& p = vertices_[static_cast<std::size_t>(faces_[f][0])];
    facing[f] = normals_[f].dot(camera_in_target - p) > 0.0;
  }
  std::vector<bool> vis(edges_.size(), false);
  for (std::size_t e = 0; e < edges_.size(); ++e)
    for (int f : edge_faces_[e]) vis[e] = vis[e] || facing[static_cast<std::size_t>(f)];
  return vis;
}

TargetModel TargetModel::truncated_box(double sx_mm, double sy_mm, double sz_mm,
                                       const Eigen::Vector3d& cut_mm) {
  const double x = sx_mm / 2, y = sy_mm / 2, z = sz_mm / 2;
  if (!(cut_mm.x() > 0 && cut_mm.x() < sx_mm && cut_mm.y() > 0 && cut_mm.y() < sy_mm &&
        cut_mm.z() > 0 && cut_mm.z() < sz_mm))
    throw std::invalid_argument("truncated_box: cut must be inside each edge");
  // 0..6: box corners other than (+,+,+); 7..9: the cut's corners on the x, y, z edges.
  std::vector<Eigen::Vector3d> v{{-x, -y, -z},
                                 {x, -y, -z},
                                 {x, y, -z},
                                 {-x, y, -z},
                                 {-x, -y, z},
                                 {x, -y, z},
                                 {-x, y, z},
                                 {x - cut_mm.x(), y, z},
                                 {x, y - cut_mm.y(), z},
                                 {x, y, z - cut_mm.z()}};
  std::vector<std::vector<int>> f{{0, 3, 2, 1},    {0, 1, 5, 4},    {0, 4, 6, 3}, {4, 5, 8, 7, 6},
                                  {1, 2, 9, 8, 5}, {3, 6, 7, 9, 2}, {7, 8, 9}};
  return TargetModel(std::move(v), std::move(f));
}

}  // namespace ephor::rambo
