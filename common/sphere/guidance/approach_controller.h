#pragma once
// The chaser's approach to the sphere (issue 15: close from 20 m to capture
// at 1 m, relative speed below 2 cm/s and the centre within 2 cm of the
// capture axis). Works on relative velocities, sensor frame of equations
// 35-37 (X right, Y up, Z boresight), metres, m/s:
//
// - along the boresight a braking profile: the closing speed wanted at a
//   distance d beyond the final approach point is v_final + sqrt(2 a d)
//   (at most max_closing), so the chaser brakes at a constant `a` well
//   inside its acceleration limit and then creeps the last final_distance
//   at v_final (the commands change only every half second, so braking
//   right down to the capture point would arrive faster than the profile);
// - across it, the offset is driven to zero: wanted lateral velocity
//   -gain * offset (at most max_lateral); the closing speed is held back
//   while the offset is outside a cone that narrows to the capture limit;
// - the chaser's velocity change per window is at most max_accel * window,
//   the chaser's own limit, so the chaser can fly what is commanded; the
//   lateral correction gets that budget first, the closing speed the rest.
//
// The wanted relative velocity v_w becomes a chaser velocity through the
// relative velocity predicted when the command takes effect: the relative
// velocity is v_target - v_chaser, so the chaser must change by v_pred - v_w.

#include <Eigen/Core>

namespace ephor::sphere {

struct ApproachConfig {
  double capture_distance_m = 1.0;
  double final_distance_m = 0.10;  // creep the last part at final speed
  double final_speed_m_s = 0.010;  // closing speed at capture (limit 0.02)
  double braking_accel_m_s2 = 0.02;
  double max_closing_m_s = 0.5;
  double lateral_gain_1_s = 0.3;
  double max_lateral_m_s = 0.3;
  double cone_offset_m = 0.01;   // allowed offset at capture distance
  double cone_slope = 0.1;       // and its growth per metre of distance to go
  double max_accel_m_s2 = 0.05;  // the chaser's limit
  double window_s = 0.5;         // commands take effect once per window
};

enum class ApproachPhase { kAcquire = 0, kClosing = 1, kFinal = 2 };
const char* to_string(ApproachPhase p);

struct ApproachCommand {
  ApproachPhase phase = ApproachPhase::kAcquire;
  Eigen::Vector3d chaser_velocity_m_s = Eigen::Vector3d::Zero();  // to fly
  Eigen::Vector3d wanted_relative_m_s = Eigen::Vector3d::Zero();  // what it aims for
};

class ApproachController {
 public:
  // Throws std::invalid_argument naming a bad setting.
  explicit ApproachController(const ApproachConfig& config = {});

  // The wanted relative velocity at relative position p.
  Eigen::Vector3d wanted_relative_velocity(const Eigen::Vector3d& position_m) const;

  // The chaser velocity to fly from the next window on, given the relative
  // state predicted then and the chaser velocity in force before it.
  ApproachCommand command(const Eigen::Vector3d& predicted_position_m,
                          const Eigen::Vector3d& predicted_velocity_m_s,
                          const Eigen::Vector3d& chaser_velocity_m_s) const;

  // Holds the chaser's velocity (no track).
  ApproachCommand hold(const Eigen::Vector3d& chaser_velocity_m_s) const;

  const ApproachConfig& config() const { return config_; }

 private:
  ApproachConfig config_;
};

}  // namespace ephor::sphere
