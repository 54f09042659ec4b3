#pragma once
// Beyond the paper's polynomial fits (section 6 suggests it: in space, with
// the target frame on the principal axes of inertia and no external forces,
// the translation is uniform): a free-floating, torque-free rigid body.
// Linear momentum constant -> the origin (the centre of mass) moves at
// constant velocity; angular momentum constant in the base frame -> the body
// rates follow Euler's equations I w' = (I w) x w, integrated with RK4,
// and the orientation follows R' = R [w]x (quaternion, renormalised).
//
// Fit: velocity and position by linear least squares; orientation R(t_ref)
// and body rates w(t_ref) at the last sample by Levenberg-Marquardt on the
// rotation residuals log(R_obs^T R_model) of every sample (numeric Jacobian;
// 6 parameters). Uncertainty: sigma_r(t)^2 = sigma_R^2 + (sigma_w |t - t_ref|)^2
// from the fit's covariance (first order, cross terms dropped).
//
// Needs the principal moments of inertia about the target frame's axes
// (from the target's model: any unit, only their ratios matter). A target
// whose frame is not on its principal axes needs its model's rotation to
// them first.

#include <Eigen/Geometry>

#include "common/rambo/polynomial_pose_predictor.h"

namespace ephor::rambo {

class RigidBodyPosePredictor : public PosePredictor {
 public:
  // principal_moments: > 0 and satisfying the triangle inequality (a real
  // body). step_s: RK4 step, s.
  explicit RigidBodyPosePredictor(const Eigen::Vector3d& principal_moments, double step_s = 0.005,
                                  int max_iterations = 30);

  const char* name() const override { return "rigid-body"; }
  bool fit(const std::vector<PoseSample>& samples, std::string* why) override;
  bool fitted() const override { return fitted_; }
  PosePrediction predict(double t_s) const override;

  // After a fit: body rates at the last sample, rad/s (target frame), and
  // the fit's RMS rotation residual, rad.
  const Eigen::Vector3d& body_rates_rad_s() const { return w_ref_; }
  double rms_rotation_residual_rad() const { return rms_residual_rad_; }

  // Torque-free motion from (q, w) over dt_s (either sign) in steps of at
  // most step_s: q maps body to base, w in the body frame, rad/s. A span
  // longer than kMaxSteps steps is cut to that (500 s at 5 ms: far beyond
  // any horizon the system predicts over; the time stays bounded); a
  // non-finite dt_s leaves (q, w) as they are.
  static constexpr int kMaxSteps = 100000;  // 500 s at 5 ms
  static void propagate(const Eigen::Vector3d& moments, double step_s, double dt_s,
                        Eigen::Quaterniond* q, Eigen::Vector3d* w);

 private:
  Eigen::VectorXd residuals(const std::vector<PoseSample>& samples, const Eigen::Quaterniond& q_ref,
                            const Eigen::Vector3d& w_ref) const;

  Eigen::Vector3d moments_;
  double step_s_;
  int max_iterations_;
  bool fitted_ = false;
  PolynomialPosePredictor translation_{1};
  double t_ref_s_ = 0.0;
  Eigen::Quaterniond q_ref_ = Eigen::Quaterniond::Identity();
  Eigen::Vector3d w_ref_ = Eigen::Vector3d::Zero();
  double sigma_orientation_rad_ = 0.0, sigma_rate_rad_s_ = 0.0, rms_residual_rad_ = 0.0;
};

}  // namespace ephor::rambo
