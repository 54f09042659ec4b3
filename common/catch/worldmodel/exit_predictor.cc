#include "common/catch/worldmodel/exit_predictor.h"

#include "common/catch/worldmodel/ball_kalman_filter.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

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

void ExitPredictor::set_pegs(std::vector<Eigen::Vector2d> centres_b_mm, double peg_radius_mm,
                             double restitution) {
  for (const auto& c : centres_b_mm)
    if (!c.allFinite()) throw std::invalid_argument("ExitPredictor: a peg centre is not finite");
  if (!centres_b_mm.empty() && !(peg_radius_mm > 0.0 && std::isfinite(peg_radius_mm)))
    throw std::invalid_argument("ExitPredictor: the peg radius must be > 0");
  if (!(restitution >= 0.0 && restitution <= 1.0))
    throw std::invalid_argument("ExitPredictor: the restitution must be in [0, 1]");
  pegs_ = std::move(centres_b_mm);
  pegs_by_y_ = pegs_;
  std::stable_sort(
      pegs_by_y_.begin(), pegs_by_y_.end(),
      [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.y() < b.y(); });
  peg_radius_mm_ = peg_radius_mm;
  restitution_ = restitution;
}

namespace {

struct RolledExit {
  bool ok = false;
  double tau_s = 0.0;
  double x_mm = 0.0;
  Eigen::Vector2d velocity = Eigen::Vector2d::Zero();
  int bounces = 0;
};

// Rolls (x, y, vx, vy) forward to y = height past pegs and rails.
RolledExit roll_past_pegs(const BoardSpec& board, const std::vector<Eigen::Vector2d>& pegs,
                          double peg_radius_mm, double restitution, double a,
                          const Eigen::Vector4d& state) {
  constexpr double kStepS = 0.0005, kHorizonS = 3.0;
  const double r = board.ball_radius_mm(), h = board.height_mm, reach = peg_radius_mm + r;
  Eigen::Vector2d p = state.head<2>(), v = state.tail<2>();
  RolledExit out;
  for (double t = 0.0; t < kHorizonS; t += kStepS) {
    v.y() += a * kStepS;
    const Eigen::Vector2d next = p + v * kStepS;
    if (next.y() >= h) {
      // Interpolate the crossing within the step.
      const double f = v.y() > 0.0 ? (h - p.y()) / (v.y() * kStepS) : 1.0;
      out.ok = true;
      out.tau_s = t + f * kStepS;
      out.x_mm = p.x() + f * v.x() * kStepS;
      out.velocity = v;
      return out;
    }
    const Eigen::Vector2d p0 = p;
    p = next;
    // Only the pegs within reach in y (`pegs` is sorted by y).
    const auto first =
        std::lower_bound(pegs.begin(), pegs.end(), p.y() - reach,
                         [](const Eigen::Vector2d& c, double y) { return c.y() < y; });
    const double y_end = p.y() + reach;
    for (auto it = first; it != pegs.end() && it->y() < y_end; ++it) {
      const Eigen::Vector2d& c = *it;
      const Eigen::Vector2d d = p - c;
      // Most pegs are far: compare squares first (no square root per peg and
      // step; ExitSpread rolls many states).
      const double dist2 = d.squaredNorm();
      if (dist2 >= reach * reach || dist2 <= 1e-18) continue;
      const double dist = std::sqrt(dist2);
      // The normal at the contact on the step's chord (see BallKalmanFilter).
      const double u = first_contact(p0, p, c, reach);
      const Eigen::Vector2d n = (p0 + u * (p - p0) - c).normalized();
      const double vn = v.dot(n);
      if (vn < 0.0) {
        v -= (1.0 + restitution) * vn * n;
        ++out.bounces;
        p = c + n * reach + v * ((1.0 - u) * kStepS);
      } else {
        p = c + (d / dist) * reach;
      }
    }
    if (p.x() < r && v.x() < 0.0) {
      p.x() = r;
      v.x() = -restitution * v.x();
    } else if (p.x() > board.width_mm - r && v.x() > 0.0) {
      p.x() = board.width_mm - r;
      v.x() = -restitution * v.x();
    }
  }
  return out;  // stalled on a peg or too slow: not ok
}

}  // namespace

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
  if (!pegs_.empty() && out.status == ExitStatus::kOk) {
    const RolledExit rolled =
        roll_past_pegs(board_, pegs_by_y_, peg_radius_mm_, restitution_, a, state);
    if (rolled.ok) {
      tau = rolled.tau_s;
      exit_x = rolled.x_mm;
      exit_vx = rolled.velocity.x();
      d = rolled.velocity.y();
      out.peg_bounces = rolled.bounces;
    } else {
      out.stalled_on_pegs = true;
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
