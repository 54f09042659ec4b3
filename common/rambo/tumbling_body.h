#pragma once
// Ground truth for a free-floating, torque-free target (constant linear and
// angular momentum): for simulators, tests and benchmarks. Uses
// RigidBodyPosePredictor::propagate with a fine step (default 0.5 ms).

#include <Eigen/Geometry>

namespace ephor::rambo {

class TumblingBody {
 public:
  // pose0: target frame in base frame at t = 0 (mm); velocity of its origin
  // (mm/s, base frame); body rates at t = 0 (rad/s, target frame); principal
  // moments about the target's axes.
  TumblingBody(const Eigen::Isometry3d& pose0, const Eigen::Vector3d& velocity_mm_s,
               const Eigen::Vector3d& body_rates_rad_s, const Eigen::Vector3d& principal_moments,
               double step_s = 0.0005);

  // Pose at t_s (any t; cheapest when queried in increasing time).
  Eigen::Isometry3d pose(double t_s);
  Eigen::Vector3d body_rates(double t_s);  // rad/s, target frame

 private:
  void advance_to(double t_s);

  Eigen::Isometry3d pose0_;
  Eigen::Vector3d v_, w0_, moments_;
  double step_s_;
  double t_ = 0.0;
  Eigen::Quaterniond q_;
  Eigen::Vector3d w_;
};

}  // namespace ephor::rambo
