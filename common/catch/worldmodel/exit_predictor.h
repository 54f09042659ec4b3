#pragma once
// ExitPredictor: where and when the ball leaves the board's bottom edge
// (y_B = height) and where it then crosses the catch plane in W. NASREM's
// Prim needs predicted, not measured, positions (paper 000, section 5.4:
// "the manipulator must move toward predicted locations of the ball").
//
// From the filter's state (x, y, vx, vy) in B and the known rolling
// acceleration a along +y, with no pegs in the way:
//   y + vy tau + a tau^2 / 2 = H   ->  tau = 2 (H - y) / (vy + D),
//   D = sqrt(vy^2 + 2 a (H - y)) = vy at the exit,
//   x_exit = x + vx tau,  vx at the exit = vx.
// (The form of tau avoids the cancellation of (D - vy) / a and holds for
// a = 0.) The uncertainty is the filter's covariance propagated through the
// Jacobian of (x_exit, t_exit, vx_exit, vy_exit) with respect to the state
// (first order): dtau/dy = -1/D, dtau/dvy = -tau/D, dD/dy = -a/D,
// dD/dvy = vy/D. The catch point is ballistic_crossing() of the exit, its
// covariance propagated through a forward-difference Jacobian.
//
// Side rails (optional, off by default: the board model has none) reflect
// the ball's centre at x = r and x = width - r, elastically; each reflection
// flips the sign of vx and of dx_exit/d(state).
//
// Pegs (optional, set_pegs): the pegs deflect the ball, and a prediction
// that ignores them only settles after the last bounce. With pegs known the
// exit is found by rolling the state forward in 0.5 ms steps under the
// rolling acceleration, bouncing off pegs and the side rails with the
// board's restitution (0.5, no friction impulse: common/catch/sim's model of
// the board). The exit's covariance stays the peg-free one (first order
// through a bounce is not meaningful; the sigma is a lower bound then).
//
// Times are relative to the state's time (s). Stateless apart from its
// configuration; const methods are safe from any thread.

#include <vector>

#include <Eigen/Core>

#include "common/catch/board_model.h"

namespace ephor::catching {

enum class ExitStatus {
  kOk,
  kPastEdge,    // the state is already at or beyond the bottom edge: tau = 0
  kNeverExits,  // no acceleration down the slope and not moving down it
  kInvalid,     // non-finite state or covariance
};
const char* to_string(ExitStatus status);

struct ExitPrediction {
  ExitStatus status = ExitStatus::kInvalid;
  double time_to_exit_s = 0.0;  // from the state's time
  double exit_x_b_mm = 0.0;     // x of B where the centre crosses y = height
  Eigen::Vector2d exit_velocity_b_mm_s = Eigen::Vector2d::Zero();  // (vx, vy) in B at the edge
  double sigma_exit_x_mm = 0.0;
  double sigma_exit_time_s = 0.0;
  // Covariance of (exit x mm, exit time s, vx mm/s, vy mm/s).
  Eigen::Matrix4d exit_covariance = Eigen::Matrix4d::Zero();
  int rail_reflections = 0;
  int peg_bounces = 0;  // with pegs known: bounces on the predicted path
  // With pegs known: the roll did not reach the edge within its 3 s horizon
  // (stuck on a peg or too slow); the peg-free exit is given then.
  bool stalled_on_pegs = false;

  // The ballistic flight from the edge to the catch plane.
  Eigen::Vector3d catch_point_w_mm = Eigen::Vector3d::Zero();  // in the catch plane, W
  double flight_s = 0.0;
  double time_to_catch_s = 0.0;  // time_to_exit_s + flight_s
  // Covariance of (catch x, y, z in W mm, catch time s); z's variance is 0.
  Eigen::Matrix4d catch_covariance = Eigen::Matrix4d::Zero();
  // sqrt of the larger eigenvalue of the horizontal (x, y of W) covariance:
  // the 1-sigma error of the catch point along its worst direction, mm.
  double sigma_catch_mm = 0.0;
  double sigma_catch_time_s = 0.0;

  bool ok() const { return status == ExitStatus::kOk || status == ExitStatus::kPastEdge; }
};

struct ExitPredictorParams {
  bool reflect_at_rails = false;
};

class ExitPredictor {
 public:
  // The rolling acceleration is 5/7 g sin(incline) unless given.
  ExitPredictor(const BoardSpec& board, const BoardPlacement& placement,
                const ExitPredictorParams& params = {});
  ExitPredictor(const BoardSpec& board, const BoardPlacement& placement, double acceleration_mm_s2,
                const ExitPredictorParams& params = {});

  // `state` = (x, y, vx, vy) in B (mm, mm/s), `covariance` its 4x4.
  ExitPrediction predict(const Eigen::Vector4d& state, const Eigen::Matrix4d& covariance) const;

  double acceleration_mm_s2() const { return acceleration_mm_s2_; }

  // The pegs' centres (B, mm) and radius; restitution of pegs and rails.
  // An empty list = no pegs. Throws std::invalid_argument for a non-finite
  // centre, a radius <= 0 or a restitution outside [0, 1].
  void set_pegs(std::vector<Eigen::Vector2d> centres_b_mm, double peg_radius_mm,
                double restitution = 0.5);
  const std::vector<Eigen::Vector2d>& pegs() const { return pegs_; }
  double peg_radius_mm() const { return peg_radius_mm_; }
  double restitution() const { return restitution_; }

 private:
  BoardSpec board_;
  BoardPlacement placement_;
  double acceleration_mm_s2_;
  ExitPredictorParams params_;
  std::vector<Eigen::Vector2d> pegs_;
  std::vector<Eigen::Vector2d> pegs_by_y_;  // the same, sorted by y: the roll checks a band
  double peg_radius_mm_ = 0.0;
  double restitution_ = 0.5;
};

}  // namespace ephor::catching
