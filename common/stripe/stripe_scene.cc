#include "common/stripe/stripe_scene.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ephor::stripe {

namespace {

// Moller-Trumbore; returns t or a negative value for a miss.
double intersect_triangle(const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                          const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                          const Eigen::Vector3d& c) {
  const Eigen::Vector3d e1 = b - a, e2 = c - a;
  const Eigen::Vector3d p = d.cross(e2);
  const double det = e1.dot(p);
  if (std::abs(det) < 1e-12) return -1.0;
  const double inv = 1.0 / det;
  const Eigen::Vector3d s = o - a;
  const double u = s.dot(p) * inv;
  if (u < 0.0 || u > 1.0) return -1.0;
  const Eigen::Vector3d q = s.cross(e1);
  const double v = d.dot(q) * inv;
  if (v < 0.0 || u + v > 1.0) return -1.0;
  return e2.dot(q) * inv;
}

bool slab(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, const Eigen::Vector3d& o,
          const Eigen::Vector3d& inv_d, double t_min, double t_max) {
  for (int k = 0; k < 3; ++k) {
    double t0 = (lo[k] - o[k]) * inv_d[k], t1 = (hi[k] - o[k]) * inv_d[k];
    if (t0 > t1) std::swap(t0, t1);
    // NaN (0 * inf when the origin is on the slab) compares false: keep going.
    if (t0 > t_min) t_min = t0;
    if (t1 < t_max) t_max = t1;
    if (t_min > t_max) return false;
  }
  return true;
}

double point_triangle_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                               const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  // Ericson, Real-Time Collision Detection, 5.1.5 (closest point on triangle).
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return (p - a).norm();
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return (p - b).norm();
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return (p - (a + d1 / (d1 - d3) * ab)).norm();
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return (p - c).norm();
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return (p - (a + d2 / (d2 - d6) * ac)).norm();
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return (p - (b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b))).norm();
  const double denom = 1.0 / (va + vb + vc);
  return (p - (a + ab * (vb * denom) + ac * (vc * denom))).norm();
}

}  // namespace

StripeScene::StripeScene() : name_("table") {}

StripeScene::StripeScene(TriangleMesh mesh, std::string name)
    : mesh_(std::move(mesh)), name_(std::move(name)) {
  const size_t n = mesh_.faces.size();
  tri_lo_.resize(n);
  tri_hi_.resize(n);
  tri_centre_.resize(n);
  order_.resize(n);
  for (size_t i = 0; i < n; ++i) {
    const auto& f = mesh_.faces[i];
    const Eigen::Vector3d &a = mesh_.vertices[f[0]], &b = mesh_.vertices[f[1]],
                          &c = mesh_.vertices[f[2]];
    tri_lo_[i] = a.cwiseMin(b).cwiseMin(c);
    tri_hi_[i] = a.cwiseMax(b).cwiseMax(c);
    tri_centre_[i] = (a + b + c) / 3.0;
    order_[i] = static_cast<int>(i);
  }
  if (n > 0) {
    nodes_.reserve(2 * n);
    build(0, static_cast<int>(n));
  }
}

StripeScene StripeScene::load(const std::string& obj_path) {
  return StripeScene(load_obj(obj_path), obj_path);
}

int StripeScene::build(int first, int count) {
  const int index = static_cast<int>(nodes_.size());
  nodes_.emplace_back();
  Eigen::Vector3d lo = tri_lo_[order_[first]], hi = tri_hi_[order_[first]];
  for (int i = first; i < first + count; ++i) {
    lo = lo.cwiseMin(tri_lo_[order_[i]]);
    hi = hi.cwiseMax(tri_hi_[order_[i]]);
  }
  nodes_[index].lo = lo;
  nodes_[index].hi = hi;
  if (count <= 4) {
    nodes_[index].first = first;
    nodes_[index].count = count;
    return index;
  }
  int axis = 0;
  (hi - lo).maxCoeff(&axis);
  const int mid = first + count / 2;
  std::nth_element(order_.begin() + first, order_.begin() + mid, order_.begin() + first + count,
                   [&](int a, int b) { return tri_centre_[a][axis] < tri_centre_[b][axis]; });
  const int left = build(first, mid - first);
  const int right = build(mid, first + count - mid);
  nodes_[index].left = left;
  nodes_[index].right = right;
  return index;
}

bool StripeScene::hit_mesh(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double t_min,
                           double& t_max, int& face, bool any) const {
  if (nodes_.empty()) return false;
  const Eigen::Vector3d inv_d = d.cwiseInverse();
  int stack[64];
  int top = 0;
  stack[top++] = 0;
  bool found = false;
  while (top > 0) {
    const Node& n = nodes_[stack[--top]];
    if (!slab(n.lo, n.hi, o, inv_d, t_min, t_max)) continue;
    if (n.left < 0) {
      for (int i = n.first; i < n.first + n.count; ++i) {
        const auto& f = mesh_.faces[order_[i]];
        const double t = intersect_triangle(o, d, mesh_.vertices[f[0]], mesh_.vertices[f[1]],
                                            mesh_.vertices[f[2]]);
        if (t > t_min && t < t_max) {
          t_max = t;
          face = order_[i];
          found = true;
          if (any) return true;
        }
      }
    } else if (top < 62) {
      stack[top++] = n.left;
      stack[top++] = n.right;
    }
  }
  return found;
}

std::optional<RayHit> StripeScene::first_hit(const Eigen::Vector3d& origin,
                                             const Eigen::Vector3d& dir, double t_min,
                                             double t_max) const {
  double best = t_max;
  int face = -1;
  // The table top z = 0.
  if (std::abs(dir.z()) > 1e-12) {
    const double t = -origin.z() / dir.z();
    if (t > t_min && t < best) best = t;
  }
  const bool on_mesh = hit_mesh(origin, dir, t_min, best, face, false);
  if (!on_mesh && !(best < t_max)) return std::nullopt;
  RayHit h;
  h.t = best;
  h.point = origin + best * dir;
  h.face = on_mesh ? face : -1;
  if (on_mesh) {
    const auto& f = mesh_.faces[face];
    h.normal = (mesh_.vertices[f[1]] - mesh_.vertices[f[0]])
                   .cross(mesh_.vertices[f[2]] - mesh_.vertices[f[0]])
                   .normalized();
  } else {
    h.normal = Eigen::Vector3d::UnitZ();
  }
  if (h.normal.dot(dir) > 0.0) h.normal = -h.normal;
  return h;
}

bool StripeScene::occluded(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, double t_min,
                           double t_max) const {
  if (std::abs(dir.z()) > 1e-12) {
    const double t = -origin.z() / dir.z();
    if (t > t_min && t < t_max) return true;
  }
  int face = -1;
  double tm = t_max;
  return hit_mesh(origin, dir, t_min, tm, face, true);
}

double StripeScene::distance_to_surface(const Eigen::Vector3d& p) const {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& f : mesh_.faces)
    best = std::min(best, point_triangle_distance(p, mesh_.vertices[f[0]], mesh_.vertices[f[1]],
                                                  mesh_.vertices[f[2]]));
  // The table top counts where no object stands on it: under an object's
  // base (a face within 0.5 mm above the table) it is not a visible surface.
  bool over_object = false;
  if (!nodes_.empty() && std::abs(p.z()) < best) {
    const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
    double tm = 0.5;
    int face = -1;
    over_object = hit_mesh(Eigen::Vector3d(p.x(), p.y(), -1e-6), up, 0.0, tm, face, true);
  }
  if (!over_object) best = std::min(best, std::abs(p.z()));
  return best;
}

}  // namespace ephor::stripe
