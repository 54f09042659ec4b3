#pragma once
// The data a scanning laser range finder delivers (paper 002, Clouse & Padgett,
// "Estimating the Position of a Sphere from Range Images", sections 2-4) and
// what a locator makes of it. Plain structs: no LCM, no I/O.
//
// Sensor frame (equations 35-37): X = R sin A cos E (right), Y = R sin E (up),
// Z = R cos A cos E (along the boresight, away from the sensor). Angles in
// radians, ranges in metres, times in seconds.

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace ephor::sphere {

// One laser pulse as measured: encoder angles and range carry the sensor's
// noise. A pulse that hit nothing has range NaN; far background returns are
// ordinary (large) ranges and must be thresholded by the locator.
struct Pulse {
  double t_s = 0.0;
  double azimuth_rad = 0.0;
  double elevation_rad = 0.0;
  double range_m = std::nan("");

  bool has_range() const { return std::isfinite(range_m); }
};

// One sweep of the fast (azimuth) axis between two turn-arounds, pulses in
// time order. `id` is the scanner's line counter (it changes when a new line
// starts; the CSV's `line` column).
struct ScanLine {
  int64_t id = 0;
  std::vector<Pulse> pulses;
};

// The lines a locator sees for one estimate: the half-second interval
// [t_begin_s, t_end_s), lines in time order.
struct Window {
  double t_begin_s = 0.0;
  double t_end_s = 0.0;
  std::vector<ScanLine> lines;
};

// What a locator returns. When `ok` is false only `reason` (and the counts)
// mean anything: "no estimate" is an expected outcome, not an exception.
struct Estimate {
  bool ok = false;
  std::string reason;
  double t_s = 0.0;                                        // time of position_m
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();    // sphere centre, sensor frame
  Eigen::Vector3d velocity_m_s = Eigen::Vector3d::Zero();  // sensor frame
  int points = 0;                                          // foreground pulses used
  int lines = 0;  // scan lines used (Scan Line Extent) or lines with points (fit)

  static Estimate none(std::string why, int points_seen = 0, int lines_seen = 0) {
    Estimate e;
    e.reason = std::move(why);
    e.points = points_seen;
    e.lines = lines_seen;
    return e;
  }
};

// Equations 35-37: spherical (A, E, R) to the sensor frame.
inline Eigen::Vector3d to_cartesian(double azimuth_rad, double elevation_rad, double range_m) {
  return {range_m * std::sin(azimuth_rad) * std::cos(elevation_rad),
          range_m * std::sin(elevation_rad),
          range_m * std::cos(azimuth_rad) * std::cos(elevation_rad)};
}

// The unit ray of a scanner direction (the inverse of equations 35-37 for R = 1).
inline Eigen::Vector3d ray_direction(double azimuth_rad, double elevation_rad) {
  return to_cartesian(azimuth_rad, elevation_rad, 1.0);
}

}  // namespace ephor::sphere
