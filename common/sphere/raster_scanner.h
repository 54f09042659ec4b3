#pragma once
// The scanning laser range finder's raster (paper 002, sections 3 and 4): the
// fast axis sweeps azimuth at constant angular velocity with instantaneous
// turn-arounds at the frame's left and right edges (so lines alternate
// direction), the slow axis moves elevation down at constant velocity and
// turns around at the bottom (then up, and at the top again down), and the
// laser fires at a constant pulse rate. A scan starts at the upper left,
// scanning right and down.
//
// The paper's pulse rate "10000 MHz" cannot be right: at 10 GHz a 1000 deg/s
// sweep would put 1e7 pulses on each degree. Its Figure 2 (a handful of
// points across the sphere at 10 m) and the timings of Tables 3-4 fit a
// 10 kHz pulse rate: 0.1 deg between pulses, 5000 pulses per half second.
// Table 2 does not depend on the pulse rate at all (frames = elevation
// travel / frame height), so it cannot confirm it.

#include <cstdint>

#include "common/sphere/scan_types.h"
#include "common/sphere/sphere_trajectory.h"

namespace ephor::sphere {

struct RasterScannerConfig {
  double azimuth_rate_deg_s = 1000.0;  // fast axis, section 3
  double elevation_rate_deg_s = 10.0;  // slow axis, section 3
  double pulse_rate_hz = 10000.0;      // 10 kHz (the paper's "10000 MHz" is a typo; see above)
  double half_extent_deg = 1.0;        // frame is [-h, h] in azimuth and elevation, centred on 0
};

// Where the scanner points at time t (true angles, before encoder noise).
struct ScanDirection {
  double azimuth_rad = 0.0;
  double elevation_rad = 0.0;
  int64_t line = 0;  // index of the azimuth sweep since t = 0
};

class RasterScanner {
 public:
  explicit RasterScanner(const RasterScannerConfig& config);

  const RasterScannerConfig& config() const { return config_; }

  // Direction at time t >= 0 from the start of the scan (upper left corner).
  ScanDirection direction_at(double t_s) const;

  // Time of pulse k (k = 0 at t = 0).
  double pulse_time(int64_t k) const { return static_cast<double>(k) / config_.pulse_rate_hz; }

  double line_duration_s() const;   // one azimuth sweep, 2h / azimuth rate
  double frame_duration_s() const;  // one elevation sweep, 2h / elevation rate
  double frames_in(double duration_s) const { return duration_s / frame_duration_s(); }
  double azimuth_step_rad() const;  // azimuth between consecutive pulses

  // Half angular extent of the frame (deg) that is `margin` times what is
  // needed to keep the whole sphere in view while it moves along `trajectory`
  // during [t0, t1] (section 4: margin 1.05). `with_range_motion` lets the
  // sphere's angular size grow as it closes in; the paper's Table 2 left that
  // out (at 1 m it gives 5.22 deg without, 5.27 with), so the default follows
  // the paper. The 5 % margin covers the difference (sphere at most 5.02 deg).
  static double required_half_extent_deg(const SphereTrajectory& trajectory, double t0_s,
                                         double t1_s, double margin = 1.05,
                                         bool with_range_motion = false);

 private:
  RasterScannerConfig config_;
};

}  // namespace ephor::sphere
