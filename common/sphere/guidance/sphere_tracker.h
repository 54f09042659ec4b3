#pragma once
// The guidance's filter of the locator's half-second estimates (paper 002,
// section 1: "these estimates will be filtered by guidance and control
// software to provide a continuous, highly accurate estimate of the position
// of the OS"): a Kalman filter with a constant-velocity model, six states
// (the sphere's centre and velocity relative to the sensor, sensor frame of
// equations 35-37, metres and m/s, scan-clock seconds), measuring position.
//
// The chaser's own velocity changes are known inputs (guidance commanded
// them): schedule_velocity_change() adds -delta-v to the relative velocity
// at the time the chaser burns, so the filter does not have to learn them
// from the measurements. What is left for the process noise is the
// unmodelled: a burn clipped or late, gravity gradient.

#include <map>
#include <optional>

#include <Eigen/Core>

namespace ephor::sphere {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

struct SphereTrackerConfig {
  double accel_noise_psd = 2e-7;            // white acceleration, (m/s^2)^2 / Hz per axis
  double initial_velocity_sigma_m_s = 0.3;  // no velocity hint
  double hint_velocity_sigma_m_s = 0.05;    // with a trusted velocity hint
  // Innovations beyond gate_chi2 (3 dof, 99.9 %) are down-weighted: the
  // measurement's covariance is inflated by d^2 / gate_chi2 (Huber), so an
  // estimate a few sigma out (Scan Line Extent's sign choice gone wrong on
  // a line or two) pulls the track only as far as one at the gate would.
  // Beyond jump_chi2 (20 sigma) they are refused: another sphere, or a
  // track gone wrong; after reinit_after_rejects refusals in a row the
  // track starts again from the measurement.
  double gate_chi2 = 16.27;
  double jump_chi2 = 400.0;
  int reinit_after_rejects = 3;
};

// The paper's accuracy at a distance as a 1-sigma per axis (m): section 1's
// requirement of 8 mm, which Figure 4 shows Scan Line Extent meets on every
// axis at 1-20 m; beyond 20 m we let it grow in proportion to the distance
// (the angular noise dominates x and y there).
Eigen::Vector3d paper_measurement_sigma_m(double distance_m);

struct TrackPrediction {
  double t_s = 0.0;
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity_m_s = Eigen::Vector3d::Zero();
  Eigen::Vector3d position_sigma_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity_sigma_m_s = Eigen::Vector3d::Zero();
};

class SphereTracker {
 public:
  enum class Update {
    kInitialised,
    kAccepted,
    kDownweighted,
    kRejected,
    kReinitialised,
    kOutOfOrder
  };

  explicit SphereTracker(const SphereTrackerConfig& config = {});

  // One position measurement at t_s with its per-axis sigma; the locator's
  // window velocity, when given, only seeds a new track.
  Update update(double t_s, const Eigen::Vector3d& position_m, const Eigen::Vector3d& sigma_m,
                const std::optional<Eigen::Vector3d>& velocity_hint_m_s = std::nullopt);

  // The relative velocity changes by dv at t_s (the chaser burns -dv).
  void schedule_velocity_change(double t_s, const Eigen::Vector3d& dv_m_s);

  // The state predicted to t_s (>= the filter's time), with the scheduled
  // changes, without changing the filter.
  TrackPrediction predict(double t_s) const;

  bool initialised() const { return initialised_; }
  double time_s() const { return t_; }
  const Vector6d& state() const { return x_; }
  const Matrix6d& covariance() const { return P_; }
  int consecutive_rejects() const { return rejects_in_a_row_; }
  void reset();

 private:
  // Moves (x, P, t) to t_s, applying scheduled changes up to t_s.
  void propagate(double t_s, Vector6d& x, Matrix6d& P, double& t,
                 std::multimap<double, Eigen::Vector3d>* consume) const;
  void initialise(double t_s, const Eigen::Vector3d& position_m, const Eigen::Vector3d& sigma_m,
                  const std::optional<Eigen::Vector3d>& velocity_hint_m_s);

  SphereTrackerConfig config_;
  bool initialised_ = false;
  double t_ = 0.0;
  Vector6d x_ = Vector6d::Zero();
  Matrix6d P_ = Matrix6d::Identity();
  int rejects_in_a_row_ = 0;
  std::multimap<double, Eigen::Vector3d> changes_;  // time -> dv of the relative velocity
};

}  // namespace ephor::sphere
