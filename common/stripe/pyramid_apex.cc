#include "common/stripe/pyramid_apex.h"

#include <cmath>

#include <Eigen/Dense>

#include "common/stripe/plane_fit.h"

namespace ephor::stripe {

std::optional<PyramidApex> PyramidApex::locate(const std::vector<Eigen::Vector3d>& cloud,
                                               const Eigen::Vector3d& initial_apex_mm,
                                               const PyramidApexOptions& options) {
  Eigen::Vector3d apex = initial_apex_mm;
  std::optional<PyramidApex> result;
  for (int it = 0; it < options.iterations; ++it) {
    std::vector<Eigen::Vector3d> faces[4];
    for (const auto& p : cloud) {
      if (p.z() < options.min_height_mm) continue;
      const double dx = p.x() - apex.x(), dy = p.y() - apex.y();
      if (std::abs(std::abs(dx) - std::abs(dy)) < options.ridge_margin_mm) continue;
      const int f = std::abs(dx) > std::abs(dy) ? (dx > 0 ? 0 : 1) : (dy > 0 ? 2 : 3);
      faces[f].push_back(p);
    }
    // A face hidden from this view (too few points) is left out: three
    // planes still meet in the apex.
    Eigen::Matrix<double, 4, 3> a = Eigen::Matrix<double, 4, 3>::Zero();
    Eigen::Vector4d b = Eigen::Vector4d::Zero();
    PyramidApex r{};
    int used = 0;
    for (int f = 0; f < 4; ++f) {
      r.face_points[f] = faces[f].size();
      r.face_rms_mm[f] = 0.0;
      if (faces[f].size() < options.min_face_points) continue;
      const auto fit = PlaneFit::fit(faces[f]);
      if (!fit) continue;
      a.row(f) = fit->normal.transpose();
      b[f] = fit->normal.dot(fit->centroid);
      r.face_rms_mm[f] = fit->rms_mm;
      ++used;
    }
    if (used < 3) return std::nullopt;
    // Normal equations (3 x 3); the planes must not be near-parallel.
    const Eigen::Matrix3d ata = a.transpose() * a;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(ata);
    if (!(es.eigenvalues()[0] > 1e-6 * es.eigenvalues()[2])) return std::nullopt;
    apex = ata.ldlt().solve(a.transpose() * b);
    r.apex_mm = apex;
    result = r;
  }
  return result;
}

}  // namespace ephor::stripe
