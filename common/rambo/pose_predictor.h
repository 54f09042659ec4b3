#pragma once
// Target motion prediction (RAMBO paper, section 6): from a time-stamped
// sequence of target poses in the robot base frame, the target's pose at a
// future time and the trajectory of any goal point fixed in the target
// frame, each with a 1-sigma uncertainty.
//
// Frames and units: a pose maps target-frame points to base-frame points
// (x_base = pose * x_target), mm; times in s on the planner's clock.

#include <string>
#include <vector>

#include <Eigen/Geometry>

namespace ephor::rambo {

struct PoseSample {
  double t_s = 0.0;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  // target in base frame, mm
};

struct PosePrediction {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  // target (or goal) in base frame, mm
  double position_sigma_mm = 0.0;   // 1-sigma of the origin's position (norm over x, y, z)
  double rotation_sigma_rad = 0.0;  // 1-sigma of the orientation (norm over three angles)
};

class PosePredictor {
 public:
  virtual ~PosePredictor() = default;
  virtual const char* name() const = 0;
  // Fits the samples (times strictly increasing, poses finite). Returns false
  // with `why` set when the samples cannot be fitted (too few, bad time
  // order, not finite); the previous fit is then dropped.
  virtual bool fit(const std::vector<PoseSample>& samples, std::string* why) = 0;
  virtual bool fitted() const = 0;
  // The target's predicted pose at t_s (after a successful fit).
  virtual PosePrediction predict(double t_s) const = 0;

  // A goal point fixed in the target frame (section 7: six coordinates in the
  // target's frame), predicted at t_s. Its position sigma adds the
  // rotation's lever arm: sqrt(sigma_p^2 + (|offset| sigma_r)^2).
  PosePrediction predict_goal(const Eigen::Isometry3d& goal_in_target, double t_s) const;
  // The goal's predicted trajectory at t0_s + k dt_s, k = 0..n-1.
  std::vector<PosePrediction> goal_trajectory(const Eigen::Isometry3d& goal_in_target, double t0_s,
                                              double dt_s, int n) const;
};

// Checks a sample sequence (>= min_samples, increasing times, finite,
// rotation orthonormal); false with a one-line reason.
bool check_samples(const std::vector<PoseSample>& samples, std::size_t min_samples,
                   std::string* why);

// ZYX (yaw about z, pitch about y, roll about x) angles of R = Rz Ry Rx, rad;
// the paper's "three rotation angles". Pitch in [-pi/2, pi/2].
Eigen::Vector3d zyx_angles(const Eigen::Matrix3d& r);
Eigen::Matrix3d from_zyx_angles(const Eigen::Vector3d& ypr);

// Rotation angle between two orientations, rad.
double rotation_angle_between(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b);

}  // namespace ephor::rambo
