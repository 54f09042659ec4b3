#pragma once
// The paper's predictor (section 6): a polynomial of time fitted by least
// squares to each of the six pose coordinates (x, y, z in mm; yaw, pitch,
// roll in rad, unwrapped along the sequence), extrapolated to the future.
// Uncertainty: the fit's residual variance propagated through the
// coefficients' covariance, sigma^2 phi(t)^T (A^T A)^-1 phi(t) per
// coordinate (zero when the fit is exact or has no spare samples).
//
// Limits (why the rigid-body model exists): Euler angles are singular at
// pitch = +-90 deg, where a tumbling body's yaw and roll swing fast, and a
// polynomial cannot follow a torque-free tumble (non-constant twist) for
// long.

#include <array>

#include <Eigen/Core>

#include "common/rambo/pose_predictor.h"

namespace ephor::rambo {

// The three rotation coordinates fitted.
//   kZyxAngles       the paper's "three rotation angles" (yaw, pitch, roll).
//   kRotationVector  log(R_mid^T R) about the middle sample's orientation
//                    R_mid: no gimbal lock while the window turns < pi from
//                    it (our addition, for a fairer comparison).
enum class RotationCoordinates { kZyxAngles, kRotationVector };

// A fitted polynomial motion as data, so that it can be sent (the predictor
// process to the planner and the simulator's scoring, rambo_prediction_t)
// and evaluated where it arrives: coordinate c at t is
// sum_k coeff[c][k] ((t - t_mid_s) / t_scale_s)^k.
struct PolynomialMotion {
  int degree = 0;  // 0..5
  RotationCoordinates rotation = RotationCoordinates::kZyxAngles;
  double t_mid_s = 0.0;                                 // centre of the basis, s (the fit's clock)
  double t_scale_s = 1.0;                               // > 0, s
  Eigen::Matrix3d r_mid = Eigen::Matrix3d::Identity();  // kRotationVector's reference orientation
  std::array<Eigen::VectorXd, 6> coeff;                 // each degree + 1 long
  // The six coordinates' basis at t_s.
  Eigen::VectorXd basis(double t_s) const;
  // The target in base at t_s (mm).
  Eigen::Isometry3d pose(double t_s) const;
  // Degree in 0..5, every coefficient sized and finite, t_scale_s > 0, r_mid a rotation.
  bool valid() const;
};

class PolynomialPosePredictor : public PosePredictor {
 public:
  // degree: 0..5 (the paper does not say; 2 = constant acceleration).
  explicit PolynomialPosePredictor(int degree = 2,
                                   RotationCoordinates rotation = RotationCoordinates::kZyxAngles);

  const char* name() const override { return "polynomial"; }
  bool fit(const std::vector<PoseSample>& samples, std::string* why) override;
  bool fitted() const override { return fitted_; }
  PosePrediction predict(double t_s) const override;

  int degree() const { return degree_; }
  RotationCoordinates rotation() const { return rotation_; }
  // After a successful fit: the fitted motion as data (predict()'s pose).
  PolynomialMotion motion() const;
  // Coordinate c (0..5: x, y, z, then the rotation coordinates) at t_s, and its sigma.
  double coordinate(int c, double t_s, double* sigma = nullptr) const;

 private:
  int degree_;
  RotationCoordinates rotation_;
  bool fitted_ = false;
  // The fit: basis in (t - t_mid) / t_scale for conditioning.
  PolynomialMotion m_;
  std::array<double, 6> residual_var_{};
  Eigen::MatrixXd ata_inv_;
};

}  // namespace ephor::rambo
