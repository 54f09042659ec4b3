#pragma once
// TrapezoidProfile: rest-to-rest motion along a path of given length with a
// speed and an acceleration cap (accelerate, cruise, decelerate; a triangle
// when the path is too short to reach the cruise speed). Units are those of
// the caller: mm and mm/s for a Cartesian path, or a path parameter in [0, 1]
// and 1/s for a joint-space segment.

namespace ephor::arm {

class TrapezoidProfile {
 public:
  // length >= 0, max_speed > 0, max_accel > 0 (throws std::invalid_argument otherwise).
  TrapezoidProfile(double length, double max_speed, double max_accel);

  double duration_s() const { return duration_; }
  double peak_speed() const { return peak_; }
  // Position along the path at time t (clamped to [0, duration]).
  double position(double t_s) const;
  // Speed along the path at time t.
  double speed(double t_s) const;

 private:
  double length_;
  double accel_;
  double peak_;    // reached speed (max_speed, or less for a triangle)
  double t_ramp_;  // duration of the acceleration phase
  double duration_;
};

}  // namespace ephor::arm
