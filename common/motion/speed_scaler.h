#pragma once
// SpeedScaler: the paper's check (section 3.6) that a requested motion is
// possible for the arm. It samples a path with inverse kinematics at the
// servo rate, computes every joint's velocity and acceleration, and when any
// joint would exceed its limit slows the WHOLE motion down by a uniform time
// scaling (velocities scale by 1/k, accelerations by 1/k^2) until every joint
// is within its limits. The tool-tip speed cap is checked the same way.
//
// Velocities and accelerations are finite differences of the samples (the
// same numbers the servo layer will see when it follows the points).

#include <functional>
#include <optional>
#include <string>

#include "common/arm/puma560.h"
#include "common/motion/trajectory.h"

namespace ephor::arm {

// The path as a function of nominal time: joints at t_nominal_s. Called with
// increasing t within one sampling pass; `previous` is the previous sample (the
// start joints at first), so inverse kinematics can stay on one branch.
// nullopt when the path cannot be followed there (the reason goes in *why).
using TimedPath = std::function<std::optional<Joints>(double t_nominal_s, const Joints& previous,
                                                      std::string* why)>;

struct ScalingConfig {
  double sample_period_s = 0.01;       // servo point spacing, s
  double max_tool_speed_mm_s = 300.0;  // cap on the tool-tip speed, mm/s
  // Fraction of the model's joint limits the motion may use: headroom for the
  // servo's interpolation between points and for its own limit checks.
  double limit_fraction = 0.95;
  double target_ratio = 0.98;  // aim this far below each (reduced) limit when scaling down
  int max_passes = 8;
  double max_stretch = 200.0;  // beyond this the motion is refused (singularity)
};

struct ScaledTrajectory {
  bool ok = false;
  std::string reason;  // when !ok
  Trajectory trajectory;
  double stretch = 1.0;             // k >= 1: the motion takes k times the nominal time
  double velocity_ratio = 0.0;      // max over samples and joints of |qd| / qd_max (<= 1 when ok)
  double acceleration_ratio = 0.0;  // max |qdd| / qdd_max
  double peak_tool_speed_mm_s = 0.0;
};

class SpeedScaler {
 public:
  SpeedScaler(const Puma560& arm, ScalingConfig config = {});

  // Samples `path` (nominal duration in s, starting at `start`) and scales it
  // down until every joint and the tool are within their limits.
  ScaledTrajectory scale(const TimedPath& path, double nominal_duration_s,
                         const Joints& start) const;

  const ScalingConfig& config() const { return config_; }

 private:
  ScaledTrajectory sample(const TimedPath& path, double nominal_duration_s, const Joints& start,
                          double stretch) const;

  Puma560 arm_;
  ScalingConfig config_;
};

}  // namespace ephor::arm
