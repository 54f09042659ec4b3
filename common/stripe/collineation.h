#pragma once
// The collineation K of paper 004, section 2: a stripe point of the image,
// X_i = [u v 1]^T, to the world point X_w = K X_i = [x y z h]^T (divide by h).
//
// With C the camera's pose and S the projector's pose in the world frame
// (frame -> world), P the camera's projection (CameraIntrinsics), R = C P^-1
// and Q = S^-1 C P^-1:
//   k_i1 = r_i1 - r_i3 q_11 / q_13,  k_i2 = r_i2 - r_i3 q_12 / q_13,
//   k_i3 = r_i4 - r_i3 q_14 / q_13   (i = 1..4).
// Why: P^-1 [u v w 1] is the camera point at inverse depth w on the pixel's
// ray; the first row of Q gives its distance from the light plane (x of S),
// which must vanish, so w = -(q11 u + q12 v + q14) / q13; substituting w into
// R [u v w 1] gives the three columns of K.
//
// "World" is whatever frame C and S are given in: the flange (C = C_T,
// S = S_T) or the base / table frame (C = T C_T, S = T S_T, T the flange pose).

#include <optional>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "common/stripe/sensor_model.h"

namespace ephor::stripe {

class Collineation {
 public:
  using Matrix43 = Eigen::Matrix<double, 4, 3>;

  // camera_pose = C, projector_pose = S (frame -> world), mm. Throws
  // std::invalid_argument when the camera's centre lies in the light plane
  // (q13 = 0: no triangulation) or the intrinsics are invalid.
  Collineation(const Eigen::Isometry3d& camera_pose, const Eigen::Isometry3d& projector_pose,
               const CameraIntrinsics& camera);

  // From the flange pose T in the world frame and the sensor's calibration:
  // C = T C_T, S = T S_T.
  static Collineation from_flange(const Eigen::Isometry3d& flange_pose,
                                  const SensorCalibration& sensor);

  const Matrix43& K() const { return k_; }
  const Eigen::Matrix4d& R() const { return r_; }
  const Eigen::Matrix4d& Q() const { return q_; }

  // The world point (mm) seen at image point (u, v) on the stripe, or nullopt
  // when the pixel's ray is parallel to the light plane or meets it behind
  // the camera.
  std::optional<Eigen::Vector3d> to_world(double u, double v) const;

 private:
  Eigen::Matrix4d r_;
  Eigen::Matrix4d q_;
  Matrix43 k_;
};

}  // namespace ephor::stripe
