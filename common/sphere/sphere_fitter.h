#pragma once
// Sphere Fitting (paper 002, section 2): the moving sphere of known radius
// R whose centre X(t) = X0 + Xdot t (eq. 3-5) best fits the foreground
// points, by least squares.
//
// Paper mode minimises eq. 6, sum [(|p_i - X(t_i)|^2 - R^2)]^2 (the paper used
// conjugate gradients; we use Levenberg-Marquardt on the same cost, so the
// minimum is the paper's and the time is not). That algebraic residual is
// 2R e + e^2 for a point e off the surface: points pushed outward by range
// noise cost more than points pushed inward, and with only the near face
// visible the centre is pulled toward the sensor by about 1.5 sigma_r^2 / R
// (7.5 mm for sigma_r = 2 cm, R = 8 cm) - the paper's z bias - and toward
// whichever side was scanned when less than a frame is (its y bias at 1 m).
//
// Beyond the paper, two residuals were tried (bench: fit-geometric-weighted,
// fit-improved). The geometric one, |p - X(t)| - R weighted by the noise
// along the surface normal, is still biased where range noise (2 cm) is not
// small against R (8 cm): a point pushed along a grazing ray lands outside
// the sphere by n^2 / 2R whatever the sign of n. The improved fit is
// maximum likelihood for the sensor's own noise instead: each point's
// measured ray is cast to the model sphere and the residual is the range
// difference r - r_hat over sigma_r^2 + (r sigma_a tan(incidence))^2 (range
// noise is Gaussian along the ray, so this has no such bias); a ray that
// misses the model sphere contributes its miss distance over r sigma_a.
// Both terms vanish at the limb, so the cost is continuous.

#include <vector>

#include "common/sphere/foreground_gate.h"
#include "common/sphere/scan_types.h"
#include "common/sphere/sphere_trajectory.h"

namespace ephor::sphere {

struct TimedPoint {
  Eigen::Vector3d p_m;  // eq. 35-37 of the measured (A, E, R)
  double t_s = 0.0;
};

// The residual each point contributes.
enum class FitResidual {
  kAlgebraic,          // eq. 6: |p - X(t)|^2 - R^2 (the paper)
  kGeometricWeighted,  // (|p - X(t)| - R - offset) / sigma along the normal
  kRayRange,           // (r - r_hat) / sigma: range along the measured ray to the model sphere
};

struct SphereFitterConfig {
  ForegroundGateConfig gate;
  double sphere_radius_m = kSphereRadiusM;
  int min_points = 12;
  int max_iterations = 50;
  double step_tolerance_m = 1e-7;
  FitResidual residual = FitResidual::kAlgebraic;
  bool noise_offset_correction = true;  // kGeometricWeighted: subtract sigma_perp^2 / 2R
  double range_sigma_m = 0.02;
  double angle_sigma_rad = 0.78e-3;

  static SphereFitterConfig paper() { return {}; }
  static SphereFitterConfig improved() {
    SphereFitterConfig c;
    c.residual = FitResidual::kRayRange;
    return c;
  }
};

struct SphereFit {
  bool converged = false;
  int iterations = 0;
  double t_ref_s = 0.0;  // time of centre_m (mean point time)
  Eigen::Vector3d centre_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity_m_s = Eigen::Vector3d::Zero();
};

class SphereFitter {
 public:
  explicit SphereFitter(const SphereFitterConfig& config = SphereFitterConfig::paper())
      : config_(config) {}

  Estimate locate(const Window& window) const;

  // The fit on given points (at least 6; no thresholding).
  SphereFit fit(const std::vector<TimedPoint>& points) const;

  const SphereFitterConfig& config() const { return config_; }

 private:
  SphereFitterConfig config_;
};

}  // namespace ephor::sphere
