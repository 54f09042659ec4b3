#include "common/stripe/pyramid_apex.h"

#include <algorithm>
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
      auto fit = PlaneFit::fit(faces[f]);
      // Points of another face or the table that fell on this side of the
      // split (a ridge seen at grazing incidence, a stripe's end) tilt the
      // plane: drop those beyond 3 sigma and fit again.
      for (int trim = 0; fit && trim < options.trim_rounds; ++trim) {
        const double limit = std::max(3.0 * fit->rms_mm, options.min_trim_mm);
        std::vector<Eigen::Vector3d> kept;
        for (const auto& p : faces[f])
          if (std::abs(fit->normal.dot(p - fit->centroid)) <= limit) kept.push_back(p);
        if (kept.size() == faces[f].size() || kept.size() < options.min_face_points) break;
        faces[f].swap(kept);
        fit = PlaneFit::fit(faces[f]);
      }
      if (!fit) continue;
      r.face_points[f] = faces[f].size();
      // A face seen along one or two stripes only (a narrow band) has its
      // plane free to turn about the band: leave it out.
      Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
      for (const auto& p : faces[f]) cov += (p - fit->centroid) * (p - fit->centroid).transpose();
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> spread(
          cov / static_cast<double>(faces[f].size()));
      if (!(std::sqrt(std::max(0.0, spread.eigenvalues()[1])) >= options.min_face_spread_mm))
        continue;
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
