#include "common/stripe/plane_fit.h"

#include <cmath>

#include <Eigen/Eigenvalues>

namespace ephor::stripe {

std::optional<PlaneFit> PlaneFit::fit(const std::vector<Eigen::Vector3d>& points) {
  if (points.size() < 3) return std::nullopt;
  PlaneFit f;
  for (const auto& p : points) {
    if (!p.allFinite()) return std::nullopt;
    f.centroid += p;
  }
  f.centroid /= static_cast<double>(points.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& p : points) cov += (p - f.centroid) * (p - f.centroid).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
  // Eigenvalues ascending: a line (two vanishing) has no plane.
  if (!(es.eigenvalues()[1] > 1e-12 * es.eigenvalues()[2])) return std::nullopt;
  f.normal = es.eigenvectors().col(0).normalized();
  if (f.normal.z() < 0.0) f.normal = -f.normal;
  double ss = 0.0;
  for (const auto& p : points) {
    const double d = f.distance(p);
    ss += d * d;
    f.max_abs_mm = std::max(f.max_abs_mm, std::abs(d));
  }
  f.count = points.size();
  f.rms_mm = std::sqrt(ss / static_cast<double>(points.size()));
  return f;
}

}  // namespace ephor::stripe
