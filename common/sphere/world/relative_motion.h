#pragma once
// The sphere's motion relative to the chaser's laser range finder (paper
// 002, section 3): the sphere (the orbital sample canister) drifts at a
// constant velocity; the chaser flies the velocity guidance commands. Both
// in the sensor frame of equations 35-37 (X right, Y up, Z along the
// boresight), whose axes are taken not to rotate (attitude held), so the
// sphere's relative position p obeys dp/dt = v_target - v_chaser.
//
// The chaser changes velocity only between measurement windows: its
// thrusters fire in a short burn at each window boundary, with the change
// limited to max_accel * window (the acceleration limit averaged over the
// window). So within every half-second window the relative motion is
// exactly linear, which is what both locating algorithms assume (section 3,
// "Motion is Linear": "the spacecraft control software knows when
// accelerations are applied"), and the simulated scan and the truth agree.

#include <Eigen/Core>

#include "common/sphere/sphere_trajectory.h"

namespace ephor::sphere {

struct RelativeMotionConfig {
  Eigen::Vector3d start_position_m = Eigen::Vector3d(0.0, 0.0, 20.0);  // sphere at t = 0
  Eigen::Vector3d target_velocity_m_s = Eigen::Vector3d::Zero();       // the sphere's drift
  Eigen::Vector3d chaser_velocity_m_s = Eigen::Vector3d::Zero();       // the chaser at t = 0
  double max_accel_m_s2 = 0.05;  // chaser's acceleration limit
  double window_s = 0.5;         // velocity changes only at multiples of this

  // Table 1's speeds at a distance: up, to the right and toward the sensor
  // (section 4's direction), x and y at Table 1's total, z 3.6 cm/s.
  static Eigen::Vector3d table1_drift(double distance_m);
};

class RelativeMotion {
 public:
  // Throws std::invalid_argument for a non-finite or out-of-range setting.
  explicit RelativeMotion(const RelativeMotionConfig& config);

  // Starts the window at t_begin_s (>= the current time, a multiple of the
  // window): moves the state there, then changes the chaser's velocity
  // toward `commanded` by at most max_accel * window (clipped along the
  // change's direction). Returns the relative motion for the window.
  SphereTrajectory begin_window(double t_begin_s, const Eigen::Vector3d& commanded_chaser_m_s);

  // Replaces the sphere (a new approach): at time t_s it is at `position_m`
  // and drifts at `target_velocity_m_s`; the chaser keeps its velocity.
  void reset_target(double t_s, const Eigen::Vector3d& position_m,
                    const Eigen::Vector3d& target_velocity_m_s);

  // The sphere's centre relative to the sensor at t_s (linear from the
  // current window's start: exact within the window).
  Eigen::Vector3d position_at(double t_s) const { return p0_ + relative_velocity() * (t_s - t0_); }
  Eigen::Vector3d relative_velocity() const { return target_velocity_ - chaser_velocity_; }
  const Eigen::Vector3d& chaser_velocity() const { return chaser_velocity_; }
  const Eigen::Vector3d& target_velocity() const { return target_velocity_; }
  double window_start_s() const { return t0_; }
  const RelativeMotionConfig& config() const { return config_; }

  // The current window as a trajectory for the range simulator.
  SphereTrajectory trajectory() const;

 private:
  RelativeMotionConfig config_;
  double t0_ = 0.0;
  Eigen::Vector3d p0_;
  Eigen::Vector3d target_velocity_;
  Eigen::Vector3d chaser_velocity_;
};

}  // namespace ephor::sphere
