#pragma once
// Scan Line Extent (paper 002, section 2 and appendix A, equations 12-40):
// each scan line that crosses the sphere gives one estimate of the centre
// from the azimuths of its two edges (the mean: the centre's azimuth; the
// extent: the slice circle's radius, hence the range and the elevation
// offset from the line), and a linear regression over the lines' times gives
// position and velocity.
//
// Where the paper's equations and its words disagree we follow the words,
// and say so beside the code: eq. 12-13 rotate by +theta, which doubles the
// line's slope instead of removing it (we rotate by -theta and back by
// +theta); eq. 19 halves the extent and eq. 21 halves it again (we keep
// lambda the full extent, so l = s tan(lambda / 2) is the slice radius).
//
// The options after `paper` switch on the corrections beyond the paper; all
// off is the paper's algorithm (see ScanLineExtentConfig::paper/improved).

#include <vector>

#include "common/sphere/foreground_gate.h"
#include "common/sphere/scan_types.h"
#include "common/sphere/sphere_trajectory.h"

namespace ephor::sphere {

struct ScanLineExtentConfig {
  ForegroundGateConfig gate;
  double sphere_radius_m = kSphereRadiusM;  // u
  int min_points_per_line = 2;
  int min_lines = 3;
  int iterations = 1;  // s_1 is the paper's choice ("adequate without further iteration")
  // More iterations only while they move the slice radius l by this much (m).
  double iteration_tolerance_m = 1e-4;

  // Beyond the paper.
  // The first and last hits lie on average half a pulse spacing inside the
  // true edges, so the hit span is one spacing short: add it. This is the
  // paper's z underestimate growing with distance (0.1 deg is 1.7 mm at 1 m,
  // 35 mm at 20 m, against a 160 mm sphere).
  bool edge_correction = false;
  // l = s sin(lambda/2) (the grazing ray) instead of tan, and the range to the
  // centre R = sqrt(s^2 + y^2) = s / cos E (eq. 27's s cos E is short by a
  // factor cos^2 E: 6 mm at the top of the sphere at 1 m).
  bool exact_geometry = false;
  // Weighted regression (section 5's suggestion): each line's x/y/z weighted
  // by the inverse of its variance propagated from the sensor noise, so
  // lines near the sphere's equator (where y = sqrt(u^2 - l^2) is ill
  // conditioned) and short lines count for less; the s average weighted per
  // point likewise (points near the chord's ends are ill conditioned).
  bool weighted_regression = false;
  // Sign of eq. 28-29 from a fit of the chord profile over each pass instead
  // of the single longest line (which noise picks at random near the centre).
  bool profile_sign = false;
  // The alignment slope of eq. 12-13 for the whole window, per scan
  // direction (the scanner's elevation rate over its azimuth rate: the
  // same for every line), from the lines' end points, instead of each line's
  // own fit over its few hits (3-4 at 20 m, where encoder noise makes the
  // per-line slope, and so the rotation, noisy).
  bool window_slope = false;
  double range_sigma_m = 0.02;  // for the weights
  double angle_sigma_rad = 0.78e-3;

  static ScanLineExtentConfig paper() { return {}; }
  static ScanLineExtentConfig improved();
};

// One scan line's estimate of the centre (equations 12-37), for tests and
// diagnostics.
struct LineExtent {
  size_t line_index = 0;  // in the window
  double t_s = 0.0;       // T_j, eq. 34
  int points = 0;
  double theta_rad = 0.0;                   // alignment rotation (slope of elevation on azimuth)
  double cos_theta = 1.0, sin_theta = 0.0;  // of theta_rad, for eq. 32-33
  double phi_rad = 0.0;                     // mean elevation after the rotation
  double mid_azimuth_rad = 0.0;             // (a_1 + a_m) / 2 after the rotation
  double lambda_rad = 0.0;                  // full azimuth extent between the edges
  double s_m = 0.0;                         // range to the slice circle's centre
  double l_m = 0.0;                         // slice circle's radius
  double y_abs_m = 0.0;                     // |y|, eq. 28
  int sign = 0;                             // +1: centre above the line (eq. 28-29), -1 below
  double azimuth_rad = 0.0, elevation_rad = 0.0, range_m = 0.0;  // A_j, E_j, R_j
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();          // eq. 35-37
  Eigen::Vector3d variance_m2 = Eigen::Vector3d::Ones();         // for weighted regression
};

// Equations 38-40 (weighted when weights are given): x(t) = x0 + xdot t.
struct LineFit {
  double x0 = 0.0;
  double slope = 0.0;
};
LineFit regress(const std::vector<double>& t, const std::vector<double>& x,
                const std::vector<double>* weights = nullptr);

class ScanLineExtent {
 public:
  explicit ScanLineExtent(const ScanLineExtentConfig& config = ScanLineExtentConfig::paper())
      : config_(config) {}

  // Position at the mean line time (the most accurate time, appendix A) and
  // velocity, or "no estimate" with the reason.
  Estimate locate(const Window& window) const;

  // The per-line estimates with signs chosen (empty if none); `why` gets the
  // reason when there are none.
  std::vector<LineExtent> line_extents(const Window& window, std::string* why = nullptr) const;

  const ScanLineExtentConfig& config() const { return config_; }

 private:
  // line_extents() into `out` (cleared first; its capacity is reused).
  void line_extents_into(const Window& window, std::vector<LineExtent>& out,
                         std::string* why) const;

  ScanLineExtentConfig config_;
};

}  // namespace ephor::sphere
