#pragma once
// AlphaBetaFilter: the constant-velocity alpha-beta tracker of paper 003,
// section 4.3, in two dimensions (the two axes are filtered independently
// with the same gains). Units are the caller's: positions in px (or mm),
// times in s, velocities in position units per s.
//
// Gains come from the tracking index (Kalata 1984, "The tracking index: a
// generalized parameter for alpha-beta and alpha-beta-gamma target
// trackers", IEEE Trans. AES-20):
//   Lambda = sigma_plant * T^2 / sigma_measurement
//   alpha  = -(Lambda^2 + 8 Lambda - (Lambda + 4) sqrt(Lambda^2 + 8 Lambda)) / 8
//   beta   =  (Lambda^2 + 4 Lambda - Lambda sqrt(Lambda^2 + 8 Lambda)) / 4
// the steady-state gains of the Kalman filter for a white-acceleration plant
// (so that beta^2 / (1 - alpha) = Lambda^2). The paper's Table 1 gives the
// plant and measurement noise of each filter but not their units. Kalata's T
// is the sampling period: we read Table 1 in px, s and take T = the interval
// between the filter's inputs (1/30 s for the first filter at the camera
// rate, 3/30 s for the second). NoiseModel::step = 1 gives the other reading
// (T = one step); predict_bench compares both. The velocity correction
// divides beta by the real interval between updates, so velocities are in
// units per second whatever T was used for the gains.
//
// Manoeuvres (paper: a sheep turned round by the arm must show up in the
// velocity "within two to three snapshots"). A filter smooth enough for 16 s
// predictions needs tens of frames to follow a 180-degree turn, so the
// filter watches its residual: a measurement farther than `maneuver_gate`
// (position units) from the prediction (Euclidean) is held back; when
// `maneuver_confirm` such measurements come in a row, the constant-velocity
// hypothesis is dropped and the filter restarts from a straight-line fit to
// the last three measurements (the held-back ones and the one before them),
// then settles again with the growing-memory gains. A single
// wild measurement (a centroid pulled by the arm's edge, a noise blob) is
// thus ignored rather than followed.
//
// Not thread-safe; one owner.

#include <Eigen/Core>

namespace ephor::worldmodel {

struct AlphaBetaGains {
  double alpha = 0.0;  // position gain, dimensionless
  double beta = 0.0;   // velocity gain, dimensionless (velocity += beta / dt * residual)
};

// Plant and measurement noise of one filter, as in the paper's Table 1.
struct NoiseModel {
  double plant_noise = 0.0;        // sigma of the plant (acceleration) noise
  double measurement_noise = 0.0;  // sigma of the measurement noise
  double step = 1.0;               // T of the tracking index, in the unit of plant_noise's time
};

// Table 1 of paper 003 (step left at 1: set it to the input interval).
inline constexpr NoiseModel kTable1First{0.01, 0.1, 1.0};
inline constexpr NoiseModel kTable1Second{0.05, 0.01, 1.0};

// Lambda = plant * step^2 / measurement. Throws std::invalid_argument unless
// all are finite and positive.
double tracking_index(const NoiseModel& noise);
// Kalata's steady-state alpha and beta for tracking index `lambda` > 0.
AlphaBetaGains gains_for_tracking_index(double lambda);

class AlphaBetaFilter {
 public:
  // `maneuver_gate` in position units; 0 turns manoeuvre restarts off.
  // `maneuver_confirm` >= 1: out-of-gate measurements in a row that restart.
  explicit AlphaBetaFilter(AlphaBetaGains gains, double maneuver_gate = 0.0,
                           int maneuver_confirm = 2);
  explicit AlphaBetaFilter(const NoiseModel& noise, double maneuver_gate = 0.0,
                           int maneuver_confirm = 2);

  // Advances the state `dt_s` seconds at constant velocity (dt_s >= 0). The
  // next update() corrects the velocity over the total time predicted since
  // the last update.
  void predict(double dt_s);
  // Corrects with a measured position `z` taken at the current (predicted)
  // time. Non-finite input is ignored and returns false.
  bool update(const Eigen::Vector2d& z);
  // Forgets everything; the next update() starts afresh.
  void reset();
  // Moves the position to `z` without touching the velocity (re-acquisition
  // after a long occlusion, where the residual says nothing about velocity).
  void relocate(const Eigen::Vector2d& z);
  // Restarts from a known state as if two measurements had been taken: the
  // growing-memory gains apply again (used to follow a manoeuvre).
  void restart(const Eigen::Vector2d& position, const Eigen::Vector2d& velocity);

  bool initialised() const { return updates_ > 0; }
  int updates() const { return updates_; }
  int maneuvers() const { return maneuvers_; }  // restarts so far
  int held_back() const { return held_back_; }  // out-of-gate measurements not (yet) used
  const Eigen::Vector2d& position() const { return position_; }
  const Eigen::Vector2d& velocity() const { return velocity_; }
  const AlphaBetaGains& gains() const { return gains_; }

 private:
  void remember(const Eigen::Vector2d& z);

  AlphaBetaGains gains_;
  double maneuver_gate_;
  int maneuver_confirm_;
  // The last three measurements and when they were taken (time of this
  // filter's clock: the sum of predict() intervals), for manoeuvre restarts.
  Eigen::Vector2d recent_z_[3];
  double recent_t_[3] = {0.0, 0.0, 0.0};
  int recent_n_ = 0;
  double clock_s_ = 0.0;
  int outside_run_ = 0;  // out-of-gate measurements in a row
  int maneuvers_ = 0;
  int held_back_ = 0;
  Eigen::Vector2d position_ = Eigen::Vector2d::Zero();
  Eigen::Vector2d velocity_ = Eigen::Vector2d::Zero();
  double since_update_s_ = 0.0;
  int updates_ = 0;
};

// The paper's double filter: the first filter (small plant noise) follows the
// measurements and turns quickly; every `subsample`-th output of the first
// filter is fed to the second (Table 1's second noise model), whose velocity
// is the smooth estimate the planner uses.
class DoubleAlphaBetaFilter {
 public:
  struct Params {
    // Defaults: Table 1 in px and s at 30 Hz, a 1 px manoeuvre gate (5 sigma
    // of the vision's 0.2 px centroid noise).
    NoiseModel first{kTable1First.plant_noise, kTable1First.measurement_noise, 1.0 / 30.0};
    NoiseModel second{kTable1Second.plant_noise, kTable1Second.measurement_noise, 3.0 / 30.0};
    int subsample = 3;           // the paper: every third point
    double maneuver_gate = 1.0;  // of the first filter, position units; 0 = off
    int maneuver_confirm = 2;    // out-of-gate measurements in a row that restart

    // Table 1 with T = the frame period (first) and subsample * frame period
    // (second), manoeuvre gate `gate` (position units).
    static Params from_frame_period(double frame_period_s, double gate);
    // Table 1 read per step (T = 1), no manoeuvre restarts.
    static Params per_step();
  };

  DoubleAlphaBetaFilter() : DoubleAlphaBetaFilter(Params{}) {}
  explicit DoubleAlphaBetaFilter(const Params& params);

  void predict(double dt_s);
  bool update(const Eigen::Vector2d& z);
  void reset();
  void relocate(const Eigen::Vector2d& z);

  bool initialised() const { return first_.initialised(); }
  // Current position: the first filter's (it is updated every frame).
  const Eigen::Vector2d& position() const { return first_.position(); }
  // Smooth velocity: the second filter's once it has two inputs, else the
  // first's.
  const Eigen::Vector2d& velocity() const {
    return second_.updates() >= 2 ? second_.velocity() : first_.velocity();
  }
  const AlphaBetaFilter& first() const { return first_; }
  const AlphaBetaFilter& second() const { return second_; }

 private:
  int subsample_;
  AlphaBetaFilter first_;
  AlphaBetaFilter second_;
  double second_pending_s_ = 0.0;  // time the second filter has not yet been predicted over
  int first_updates_since_feed_ = 0;
};

}  // namespace ephor::worldmodel
