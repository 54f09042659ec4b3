#pragma once
// Joint trajectories sampled at a fixed time step, as section 9 of the RAMBO
// paper lays them out: the tool's trajectory and a goal point's predicted
// trajectory "sampled with the same time increments". Joints in rad, PUMA
// 560 order; times in s on the planner's clock.

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "common/arm/puma560.h"

namespace ephor::rambo {

using arm::Joints;

struct JointSample {
  Joints q = Joints::Zero();    // rad
  Joints qd = Joints::Zero();   // rad/s
  Joints qdd = Joints::Zero();  // rad/s^2
};

class SampledJointTrajectory {
 public:
  SampledJointTrajectory() = default;
  // samples[k] is the state at t0_s + k dt_s. Throws std::invalid_argument
  // for dt_s <= 0, no samples, or a non-finite value.
  SampledJointTrajectory(double t0_s, double dt_s, std::vector<JointSample> samples);

  // Positions only: velocities and accelerations by central differences
  // (one-sided at the ends). Needs at least 3 samples.
  static SampledJointTrajectory from_positions(double t0_s, double dt_s,
                                               const std::vector<Joints>& q);
  // n samples of fn(t) from t0_s.
  static SampledJointTrajectory from_function(double t0_s, double dt_s, int n,
                                              const std::function<JointSample(double)>& fn);

  double t0_s() const { return t0_s_; }
  double dt_s() const { return dt_s_; }
  double t_end_s() const { return t0_s_ + dt_s_ * static_cast<double>(samples_.size() - 1); }
  bool covers(double t_s) const { return t_s >= t0_s_ - 1e-9 && t_s <= t_end_s() + 1e-9; }
  const std::vector<JointSample>& samples() const { return samples_; }

  // State at t_s: q by cubic Hermite between samples (exact for cubics), qd
  // and qdd linearly. t_s is clamped to [t0, t_end]: ask covers() first.
  JointSample at(double t_s) const;

 private:
  double t0_s_ = 0.0;
  double dt_s_ = 1.0;
  std::vector<JointSample> samples_;
};

// A goal point's tool-pose trajectory (base frame, mm) in joint space: the
// inverse kinematics at every sample, each solution the one nearest the
// previous (starting nearest `start_near`), derivatives by differences.
// When a sample is out of reach or the branch would jump (more than
// max_step_rad on a joint between samples): with `partial`, the samples
// before it (if at least 3), else nullopt; `why` says which and when.
std::optional<SampledJointTrajectory> joint_trajectory_from_poses(
    const arm::Puma560& arm, const std::function<Eigen::Isometry3d(double)>& tool_pose,
    const Joints& start_near, double t0_s, double dt_s, int n, std::string* why,
    double max_step_rad = 0.5, bool partial = false);

}  // namespace ephor::rambo
