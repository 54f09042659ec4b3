#include "common/catch/worldmodel/exit_predictor.h"

#include <algorithm>
#include <cmath>

namespace ephor::catching {

const char* to_string(ExitStatus status) {
  switch (status) {
    case ExitStatus::kOk:
      return "ok";
    case ExitStatus::kPastEdge:
      return "past edge";
    case ExitStatus::kNeverExits:
      return "never exits";
    case ExitStatus::kInvalid:
      return "invalid";
  }
  return "?";
}

ExitPredictor::ExitPredictor(const BoardSpec& board, const BoardPlacement& placement,
                             const ExitPredictorParams& params)
    : ExitPredictor(board, placement, 5.0 / 7.0 * kGravityMmS2 * std::sin(placement.incline_rad),
                    params) {}

ExitPredictor::ExitPredictor(const BoardSpec& board, const BoardPlacement& placement,
                             double acceleration_mm_s2, const ExitPredictorParams& params)
    : board_(board),
      placement_(placement),
      acceleration_mm_s2_(acceleration_mm_s2),
      params_(params) {}

ExitPrediction ExitPredictor::predict(const Eigen::Vector4d& state,
                                      const Eigen::Matrix4d& covariance) const {
  ExitPrediction out;
  if (!state.allFinite() || !covariance.allFinite()) return out;
  const double x = state(0), y = state(1), vx = state(2), vy = state(3);
  const double a = acceleration_mm_s2_, h = board_.height_mm;

  // J: d(x_exit, t_exit, vx_exit, vy_exit) / d(x, y, vx, vy).
  Eigen::Matrix4d j = Eigen::Matrix4d::Zero();
  double tau = 0.0, d = vy;
  if (y >= h) {
    out.status = ExitStatus::kPastEdge;
    j(0, 0) = 1.0;
    j(2, 2) = 1.0;
    j(3, 3) = 1.0;
  } else {
    const double rest = h - y;
    d = std::sqrt(std::max(0.0, vy * vy + 2.0 * a * rest));
    if (!(vy + d > 0.0)) {
      out.status = ExitStatus::kNeverExits;
      return out;
    }
    out.status = ExitStatus::kOk;
    tau = 2.0 * rest / (vy + d);
    const double dtau_dy = -1.0 / d, dtau_dvy = -tau / d;
    j(0, 0) = 1.0;
    j(0, 1) = vx * dtau_dy;
    j(0, 2) = tau;
    j(0, 3) = vx * dtau_dvy;
    j(1, 1) = dtau_dy;
    j(1, 3) = dtau_dvy;
    j(2, 2) = 1.0;
    j(3, 1) = -a / d;
    j(3, 3) = vy / d;
  }
  double exit_x = x + vx * tau;
  double exit_vx = vx;
  if (params_.reflect_at_rails) {
    const double r = board_.ball_radius_mm();
    const double span = board_.width_mm - 2.0 * r;
    if (span > 0.0) {
      // Unfold: between the rails the centre's x is a triangle wave of the
      // free path; q = how many rail-widths the free path has run past.
      const double u = exit_x - r;
      const double q = std::floor(u / span);
      double m = u - q * span;  // [0, span)
      const bool flipped = std::fmod(std::abs(q), 2.0) == 1.0;
      if (flipped) m = span - m;
      out.rail_reflections = static_cast<int>(std::abs(q));
      exit_x = r + m;
      if (flipped) {
        exit_vx = -vx;
        j.row(0) *= -1.0;
        j.row(2) *= -1.0;
      }
    }
  }
  out.time_to_exit_s = tau;
  out.exit_x_b_mm = exit_x;
  out.exit_velocity_b_mm_s = Eigen::Vector2d(exit_vx, d);
  out.exit_covariance = j * covariance * j.transpose();
  out.sigma_exit_x_mm = std::sqrt(std::max(0.0, out.exit_covariance(0, 0)));
  out.sigma_exit_time_s = std::sqrt(std::max(0.0, out.exit_covariance(1, 1)));

  // The flight and its Jacobian with respect to (x_exit, t_exit, vx, vy).
  const BallisticCrossing c = ballistic_crossing(board_, placement_, exit_x, exit_vx, d);
  out.catch_point_w_mm = c.point_w_mm;
  out.flight_s = c.flight_s;
  out.time_to_catch_s = tau + c.flight_s;
  Eigen::Matrix4d jc = Eigen::Matrix4d::Zero();
  jc(3, 1) = 1.0;                              // catch time moves with the exit time
  const double steps[3] = {1e-3, 1e-3, 1e-3};  // mm, mm/s, mm/s
  const int columns[3] = {0, 2, 3};
  for (int i = 0; i < 3; ++i) {
    double e[3] = {exit_x, exit_vx, d};
    e[i] += steps[i];
    const BallisticCrossing ci = ballistic_crossing(board_, placement_, e[0], e[1], e[2]);
    jc.block<3, 1>(0, columns[i]) = (ci.point_w_mm - c.point_w_mm) / steps[i];
    jc(3, columns[i]) = (ci.flight_s - c.flight_s) / steps[i];
  }
  out.catch_covariance = jc * out.exit_covariance * jc.transpose();
  // The largest eigenvalue of the horizontal 2x2 block, in closed form.
  const double sxx = out.catch_covariance(0, 0), syy = out.catch_covariance(1, 1),
               sxy = out.catch_covariance(0, 1);
  const double half_trace = 0.5 * (sxx + syy);
  const double radius = std::sqrt(0.25 * (sxx - syy) * (sxx - syy) + sxy * sxy);
  out.sigma_catch_mm = std::sqrt(std::max(0.0, half_trace + radius));
  out.sigma_catch_time_s = std::sqrt(std::max(0.0, out.catch_covariance(3, 3)));
  return out;
}

}  // namespace ephor::catching
