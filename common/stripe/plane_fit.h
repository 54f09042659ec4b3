#pragma once
// Least-squares plane through points (total least squares: the normal is the
// direction of least spread about the centroid). Used for the random error of
// section 5 ("a flat surface ... the thickness of the band") and for the
// projector plane of section 4.

#include <optional>
#include <vector>

#include <Eigen/Core>

namespace ephor::stripe {

struct PlaneFit {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // unit; sign: +z-ish when possible
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  double rms_mm = 0.0;      // 1 sigma of the signed point-to-plane distances
  double max_abs_mm = 0.0;  // worst |distance|
  size_t count = 0;

  double distance(const Eigen::Vector3d& p) const { return normal.dot(p - centroid); }

  // nullopt for fewer than 3 points, non-finite points or a degenerate
  // (collinear) set.
  static std::optional<PlaneFit> fit(const std::vector<Eigen::Vector3d>& points);
};

}  // namespace ephor::stripe
