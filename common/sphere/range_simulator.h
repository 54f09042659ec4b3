#pragma once
// The paper's range-data simulator (section 4): a perfect raster scan, a ray
// cast from the sensor origin in the scanner's direction at each pulse time
// to the moving sphere, the range to the first intersection, then Gaussian
// noise on range and on each encoder angle (section 3: sigma 2.0 cm and
// 0.78 mrad). No beam footprint, no light travel time (0.13 us at 20 m).
// Beyond the paper: an optional far background (a wall at >= 50 m behind
// the lower part of the frame) that the locators must threshold away.

#include <cstdint>
#include <optional>
#include <random>
#include <vector>

#include "common/sphere/raster_scanner.h"
#include "common/sphere/scan_types.h"
#include "common/sphere/sphere_trajectory.h"

namespace ephor::sphere {

// Range (m) along the unit ray `direction` from `origin` to the first
// intersection with the sphere, or nullopt if it misses (or the sphere is
// behind the origin). A sensor inside the sphere sees its inner wall.
std::optional<double> ray_sphere_range(const Eigen::Vector3d& origin,
                                       const Eigen::Vector3d& direction,
                                       const Eigen::Vector3d& centre, double radius_m);

struct RangeNoise {
  double range_sigma_m = 0.02;       // section 3
  double angle_sigma_rad = 0.78e-3;  // each encoder, section 3
};

struct FarBackground {
  bool enabled = false;
  double range_m = 60.0;             // returns at least 50 m (the threshold)
  double below_elevation_deg = 0.0;  // pulses pointing lower than this hit the wall
};

struct RangeSimulatorConfig {
  RasterScannerConfig scanner;
  SphereTrajectory sphere;
  RangeNoise noise;
  FarBackground background;
  uint64_t seed = 1;
};

class RangeSimulator {
 public:
  explicit RangeSimulator(const RangeSimulatorConfig& config);

  // The pulses of [t_begin, t_begin + duration) grouped into scan lines, the
  // scanner restarting at the upper left at t_begin (each trial is a fresh
  // raster). Line ids start at first_line_id. Noise draws continue from the
  // simulator's generator, so consecutive calls give independent noise.
  std::vector<ScanLine> scan(double t_begin_s, double duration_s, int64_t first_line_id = 0);

  const RangeSimulatorConfig& config() const { return config_; }
  const RasterScanner& scanner() const { return scanner_; }

  // The paper's trial at a distance (section 4): the frame 105 % of what
  // the sphere needs in [t_begin, t_begin + 0.5 s], the centre through
  // (0, 0, distance) at t_begin + 0.25 s, Table 1's speeds, section 3's noise.
  static RangeSimulatorConfig paper_trial(double distance_m, uint64_t seed, double t_begin_s = 0.0,
                                          double duration_s = 0.5);

 private:
  RangeSimulatorConfig config_;
  RasterScanner scanner_;
  std::mt19937_64 rng_;
};

}  // namespace ephor::sphere
