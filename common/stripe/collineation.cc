#include "common/stripe/collineation.h"

#include <cmath>
#include <stdexcept>

namespace ephor::stripe {

Collineation::Collineation(const Eigen::Isometry3d& camera_pose,
                           const Eigen::Isometry3d& projector_pose,
                           const CameraIntrinsics& camera) {
  if (!camera.valid()) throw std::invalid_argument("Collineation: invalid camera intrinsics");
  r_ = camera_pose.matrix() * camera.inverse_projection_matrix();
  q_ = projector_pose.inverse().matrix() * r_;
  // q13 is the camera centre's distance from the light plane (mm) per unit
  // inverse depth: zero means the camera sits in the plane.
  if (!(std::abs(q_(0, 2)) > 1e-9))
    throw std::invalid_argument("Collineation: camera centre lies in the light plane (q13 = 0)");
  for (int i = 0; i < 4; ++i) {
    const double ri3 = r_(i, 2) / q_(0, 2);
    k_(i, 0) = r_(i, 0) - ri3 * q_(0, 0);
    k_(i, 1) = r_(i, 1) - ri3 * q_(0, 1);
    k_(i, 2) = r_(i, 3) - ri3 * q_(0, 3);
  }
}

Collineation Collineation::from_flange(const Eigen::Isometry3d& flange_pose,
                                       const SensorCalibration& sensor) {
  return Collineation(flange_pose * sensor.camera_in_flange,
                      flange_pose * sensor.projector_in_flange, sensor.camera);
}

std::optional<Eigen::Vector3d> Collineation::to_world(double u, double v) const {
  // Inverse depth on the ray: must be positive (in front of the camera).
  const double w = -(q_(0, 0) * u + q_(0, 1) * v + q_(0, 3)) / q_(0, 2);
  if (!std::isfinite(w) || w <= 1e-12) return std::nullopt;
  const Eigen::Vector4d xw = k_ * Eigen::Vector3d(u, v, 1.0);
  if (!(std::abs(xw[3]) > 1e-15)) return std::nullopt;
  return Eigen::Vector3d(xw.head<3>() / xw[3]);
}

}  // namespace ephor::stripe
