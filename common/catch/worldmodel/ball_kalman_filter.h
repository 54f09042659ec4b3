#pragma once
// BallKalmanFilter: the ball's position and velocity in the board plane,
// state (x, y, vx, vy) in B (mm, mm/s), for a solid ball rolling without
// slipping down the incline. Its acceleration along +y of B is known,
// a = 5/7 g sin(incline) (the 5/7 is m / (m + I/r^2) with I = 2/5 m r^2),
// and enters as a control input, so the filter estimates a constant-velocity
// residual rather than the acceleration itself.
//
// Model, with T the step:
//   x' = x + vx T,             vx' = vx
//   y' = y + vy T + a T^2 / 2,  vy' = vy + a T
// plus white acceleration noise, accel_sigma_x / accel_sigma_y per axis (the
// discrete white-noise-acceleration Q = sigma^2 [T^4/4, T^3/2; T^3/2, T^2]
// per axis): rolling resistance, a board that is not quite flat, an
// incline known to a degree (1 degree of incline error is ~110 mm/s^2).
//
// Peg bounces. A bounce changes the velocity within a few ms, far faster
// than the white-noise model allows, so the filter would follow it only
// over many frames. The filter therefore tests each innovation: when the
// normalised innovation squared NIS = nu' S^-1 nu exceeds
// `bounce_nis_threshold` (chi-square, 2 degrees of freedom: 16 is exceeded
// by chance once in ~3000 frames), a velocity impulse of
// `bounce_velocity_sigma_mm_s` per axis is assumed at an unknown time
// (uniform) within the interval T since the last update: P += Qb [T^2/3,
// T/2; T/2, 1] per axis. The same measurement already corrects the velocity
// through the cross covariance; the correlation of sqrt(3)/2 (not 1) leaves
// a quarter of Qb in the velocity for the next frames to settle (with the
// impulse put at the start of the interval the filter became overconfident
// after one frame and needed 0.14 s instead of 0.04-0.08 s).
//
// Tuning (ball_kalman_filter_test.cc, 60 Hz, 1 mm measurement noise, ten
// seeds): accel_sigma_y 200 mm/s^2 covers a 2-degree incline error; across
// the slope nothing but rolling resistance acts, accel_sigma_x 30 mm/s^2
// (10 changed the exit-x sigma half a second ahead only from 2.13 to
// 2.05 mm: the data, not the model, limit it). Measured: worst velocity
// error after 0.3 s 6.6-14.3 mm/s, no false bounce; after a 650 mm/s peg
// bounce the velocity error is back under 50 mm/s within 0.04-0.075 s
// (0.41 s without inflation). bounce_velocity_sigma 800 mm/s is the size of
// a peg bounce at the board's typical 1-2 m/s. Measurement noise R is the
// caller's (BallWorldModel maps its pixel sigma through the ray).
//
// Known pegs (set_pegs, optional): the mean is carried through a predict
// in steps of at most 2 ms, and a step that puts the ball into a peg
// reflects its velocity off the peg (restitution e, no friction) - the
// bounce the inflation above would otherwise have to find from the
// measurements; the velocity's covariance is carried through the same
// reflections (I - (1 + e) n n'). Pegs are circles of radius peg_radius
// around the given centres (B, mm); the ball's own radius is added.
//
// A modelled bounce is itself uncertain: the contact normal's angle comes
// from where the ball meets the peg, and that is known only to the peg's
// survey error and the ball's position error across its path. With b the
// impact offset across the path, reach R and alpha the angle between the
// incoming velocity and the normal, d(theta) = db / (R cos alpha): a
// grazing contact (cos alpha -> 0) leaves the outgoing direction nearly
// unknown. The predict step therefore adds, per modelled bounce, the
// velocity covariance sigma_theta^2 g g' with g = dv'/dtheta =
// -(1 + e) ((v.t) n + (v.n) t) (t the normal turned by 90 degrees) and
// sigma_theta^2 = (peg_sigma^2 + lateral position variance) / (R cos
// alpha)^2 (cos alpha floored at bounce_min_cos), plus the restitution's
// error sigma_e^2 (v.n)^2 n n'; the part accrued after the bounce within
// the step moves the position as well. Without it the filter, told its
// bounced velocity was as good as before, followed a 40 mm/s error for
// ten frames (seed 1, ball 0 of the perception harness).
//
// Not thread-safe; one owner.

#include <vector>

#include <Eigen/Core>

namespace ephor::catching {

struct BallKalmanParams {
  double acceleration_mm_s2 = 0.0;  // known, along +y of B
  // White acceleration noise: across the slope (x) only rolling resistance
  // and a board not quite level sideways; down it (y) also the incline's
  // error (1 degree is ~110 mm/s^2).
  double accel_sigma_x_mm_s2 = 30.0;
  double accel_sigma_y_mm_s2 = 200.0;
  double initial_velocity_sigma_mm_s = 1500.0;
  double bounce_nis_threshold = 16.0;  // 0 or less: never inflate
  double bounce_velocity_sigma_mm_s = 800.0;
  // Modelled peg bounces (set_pegs): the pegs' survey error (mm, per axis),
  // the restitution's error and the floor of cos(alpha) (see above).
  double peg_position_sigma_mm = 0.5;
  double restitution_sigma = 0.05;
  double bounce_min_cos = 0.2;
};

struct KalmanUpdateResult {
  bool applied = false;  // false for non-finite input or before initialise()
  double nis = 0.0;      // normalised innovation squared before any inflation
  bool bounce = false;   // the process noise was inflated for a bounce
  Eigen::Vector2d innovation = Eigen::Vector2d::Zero();  // z - H x, mm
};

// Where on the segment p0 -> p1 (mm) a ball's centre first comes within
// reach_mm of `centre`, as the fraction u in [0, 1] (0 when p0 is within
// it already, 1 when the segment never is). Used by the filter's and the
// exit predictor's peg bounces.
double first_contact(const Eigen::Vector2d& p0, const Eigen::Vector2d& p1,
                     const Eigen::Vector2d& centre, double reach_mm);

class BallKalmanFilter {
 public:
  using State = Eigen::Matrix<double, 4, 1>;  // x, y (mm), vx, vy (mm/s), B
  using Covariance = Eigen::Matrix<double, 4, 4>;

  // Throws std::invalid_argument for non-finite or negative parameters.
  explicit BallKalmanFilter(const BallKalmanParams& params);

  // Starts from a measured position `z` (mm, B) with covariance `r` and a
  // velocity guess with initial_velocity_sigma per axis.
  void initialise(const Eigen::Vector2d& z, const Eigen::Matrix2d& r,
                  const Eigen::Vector2d& velocity = Eigen::Vector2d::Zero());
  // Advances the state by dt_s >= 0 (negative or non-finite is ignored).
  void predict(double dt_s);
  // Corrects with a position `z` (mm, B) of covariance `r` (mm^2) taken at
  // the current (predicted) time.
  KalmanUpdateResult update(const Eigen::Vector2d& z, const Eigen::Matrix2d& r);
  void reset();
  // The pegs the predict step bounces the ball off (an empty list = none).
  // reach_mm = peg radius + ball radius. Throws std::invalid_argument for a
  // non-finite centre, reach_mm <= 0 or a restitution outside [0, 1].
  void set_pegs(std::vector<Eigen::Vector2d> centres_b_mm, double reach_mm,
                double restitution = 0.5);
  int peg_bounces() const { return peg_bounces_; }  // predicted bounces so far

  bool initialised() const { return initialised_; }
  const State& state() const { return x_; }
  const Covariance& covariance() const { return p_; }
  Eigen::Vector2d position() const { return x_.head<2>(); }
  Eigen::Vector2d velocity() const { return x_.tail<2>(); }
  double acceleration_mm_s2() const { return params_.acceleration_mm_s2; }
  int updates() const { return updates_; }
  int bounces() const { return bounces_; }  // inflations so far
  const BallKalmanParams& params() const { return params_; }

 private:
  // The covariance a modelled bounce adds to the outgoing velocity (see
  // the header comment); notes rest_s, the step's time after the bounce.
  Eigen::Matrix2d bounce_velocity_covariance(const Eigen::Vector2d& v_in, const Eigen::Vector2d& n,
                                             const Eigen::Matrix2d& position_cov, double rest_s);

  BallKalmanParams params_;
  bool initialised_ = false;
  State x_ = State::Zero();
  Covariance p_ = Covariance::Zero();
  double since_update_s_ = 0.0;
  int updates_ = 0;
  int bounces_ = 0;
  std::vector<Eigen::Vector2d> pegs_;
  double peg_reach_mm_ = 0.0;
  double restitution_ = 0.5;
  int peg_bounces_ = 0;
  double last_bounce_rest_s_ = 0.0;
};

}  // namespace ephor::catching
