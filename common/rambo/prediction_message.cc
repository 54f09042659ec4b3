#include "common/rambo/prediction_message.h"

#include <cmath>

namespace ephor::rambo {

std::optional<FittedMotion> motion_from_message(const rambo_prediction_t& m, double t_ref_s,
                                                std::string* why) {
  if (!m.fitted) {
    if (why) *why = "not fitted: " + m.reason;
    return std::nullopt;
  }
  FittedMotion f;
  f.t_ref_s = t_ref_s;
  f.position_mm = Eigen::Vector3d(m.position_mm[0], m.position_mm[1], m.position_mm[2]);
  f.velocity_mm_s = Eigen::Vector3d(m.velocity_mm_s[0], m.velocity_mm_s[1], m.velocity_mm_s[2]);
  f.orientation = Eigen::Quaterniond(m.orientation_wxyz[0], m.orientation_wxyz[1],
                                     m.orientation_wxyz[2], m.orientation_wxyz[3]);
  f.body_rates_rad_s =
      Eigen::Vector3d(m.body_rates_rad_s[0], m.body_rates_rad_s[1], m.body_rates_rad_s[2]);
  f.principal_moments =
      Eigen::Vector3d(m.principal_moments[0], m.principal_moments[1], m.principal_moments[2]);
  if (m.poly_terms != 0) {
    if (m.poly_terms < 0 || m.poly_terms > 6 || (m.poly_rotation != 0 && m.poly_rotation != 1)) {
      if (why)
        *why = "polynomial of " + std::to_string(m.poly_terms) + " terms, rotation kind " +
               std::to_string(m.poly_rotation) + ": not one the predictor fits (1-6 terms, 0 or 1)";
      return std::nullopt;
    }
    PolynomialMotion p;
    p.degree = m.poly_terms - 1;
    p.rotation = m.poly_rotation == 1 ? RotationCoordinates::kRotationVector
                                      : RotationCoordinates::kZyxAngles;
    p.t_mid_s = t_ref_s + m.poly_t_mid_s;
    p.t_scale_s = m.poly_t_scale_s;
    const Eigen::Quaterniond q(m.poly_r_mid_wxyz[0], m.poly_r_mid_wxyz[1], m.poly_r_mid_wxyz[2],
                               m.poly_r_mid_wxyz[3]);
    if (!q.coeffs().allFinite() || std::abs(q.norm() - 1.0) > 1e-6) {
      if (why) *why = "polynomial's reference orientation is not a unit quaternion";
      return std::nullopt;
    }
    p.r_mid = q.toRotationMatrix();
    for (int c = 0; c < 6; ++c) {
      p.coeff[static_cast<std::size_t>(c)].resize(p.degree + 1);
      for (int k = 0; k <= p.degree; ++k)
        p.coeff[static_cast<std::size_t>(c)][k] = m.poly_coeff[6 * k + c];
    }
    f.polynomial = p;
  }
  if (!f.finite()) {
    if (why) *why = "not finite, or a polynomial with a scale <= 0";
    return std::nullopt;
  }
  f.orientation.normalize();
  return f;
}

void polynomial_to_message(const PolynomialMotion& p, double t_ref_s, rambo_prediction_t* out) {
  out->model = "polynomial";
  out->poly_terms = p.degree + 1;
  out->poly_rotation = p.rotation == RotationCoordinates::kRotationVector ? 1 : 0;
  out->poly_t_mid_s = p.t_mid_s - t_ref_s;
  out->poly_t_scale_s = p.t_scale_s;
  const Eigen::Quaterniond q(p.r_mid);
  out->poly_r_mid_wxyz[0] = q.w();
  out->poly_r_mid_wxyz[1] = q.x();
  out->poly_r_mid_wxyz[2] = q.y();
  out->poly_r_mid_wxyz[3] = q.z();
  for (double& c : out->poly_coeff) c = 0.0;
  for (int c = 0; c < 6; ++c)
    for (int k = 0; k <= p.degree; ++k)
      out->poly_coeff[6 * k + c] = p.coeff[static_cast<std::size_t>(c)][k];
}

void no_polynomial(rambo_prediction_t* out) {
  out->poly_terms = 0;
  out->poly_rotation = 0;
  out->poly_t_mid_s = 0.0;
  out->poly_t_scale_s = 1.0;
  out->poly_r_mid_wxyz[0] = 1.0;
  out->poly_r_mid_wxyz[1] = out->poly_r_mid_wxyz[2] = out->poly_r_mid_wxyz[3] = 0.0;
  for (double& c : out->poly_coeff) c = 0.0;
}

}  // namespace ephor::rambo
