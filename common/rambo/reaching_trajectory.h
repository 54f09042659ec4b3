#pragma once
// A reaching trajectory (RAMBO paper, section 8): the tagging joint leaves
// its current trajectory p0 at t0 and lands on the goal trajectory pg at
// t0 + T, with position and velocity continuous at both ends.
//
// Space: joint space (rad). The paper interpolates in location/direction
// space; both its formulas apply to any vector space, and in joint space the
// limits the paper names (section 9: positions, velocities, accelerations
// "imposed by the robot design") are checked exactly at each sample, no
// inverse kinematics is needed along the way (no singularity or branch flip
// mid-motion), and orientation needs no angle-space interpolation. The cost:
// the tool's Cartesian path is not a straight line, so collision with the
// target is checked on the forward kinematics of every sample instead.
//
// Methods:
//   kCubicSpline  one cubic per joint (Hermite): q(t0) = p0(t0),
//                 q'(t0) = p0'(t0), q(t0+T) = pg(t0+T), q'(t0+T) = pg'(t0+T).
//                 Acceleration jumps at both ends (finite).
//   kBlend        p_r(t) = f_T(t - t0) pg(t) + (1 - f_T(t - t0)) p0(t), with
//                 f_T(s) = 2 (s/T)^2 for s <= T/2 and 1 - 2 ((s - T)/T)^2
//                 after. The paper prints the first piece as 2 (t/T)^4, which
//                 is 1/8 at T/2 against the second piece's 1/2: a jump, and
//                 not the "piecewise quadratic ... continuous derivatives" its
//                 text describes. With exponent 2 both pieces meet at 1/2
//                 with slope 2/T, so we take that as meant (tested).

#include <memory>

#include "common/rambo/joint_trajectory.h"

namespace ephor::rambo {

enum class ReachingMethod { kCubicSpline, kBlend };
const char* to_string(ReachingMethod m);

// f_T and its derivatives with respect to s = (t - t0) / T in [0, 1]
// (clamped): divide df by T and d2f by T^2 for time derivatives.
struct BlendValue {
  double f = 0.0;
  double df = 0.0;
  double d2f = 0.0;
};
BlendValue blend_fraction(double s);
// The paper's formula as printed (first piece 2 s^4), for the record.
double blend_fraction_as_printed(double s);

class ReachingTrajectory {
 public:
  // current and goal must cover [t0_s, t0_s + duration_s]. Throws
  // std::invalid_argument when they do not, or duration_s <= 0.
  ReachingTrajectory(ReachingMethod method, std::shared_ptr<const SampledJointTrajectory> current,
                     std::shared_ptr<const SampledJointTrajectory> goal, double t0_s,
                     double duration_s);

  ReachingMethod method() const { return method_; }
  double t0_s() const { return t0_s_; }
  double duration_s() const { return duration_s_; }
  double t_land_s() const { return t0_s_ + duration_s_; }
  const SampledJointTrajectory& current() const { return *current_; }
  const SampledJointTrajectory& goal() const { return *goal_; }

  // Joint state at t_s: the current trajectory before t0, the reaching
  // trajectory on [t0, t0 + T], the goal trajectory after (while covered).
  JointSample at(double t_s) const;

 private:
  ReachingMethod method_;
  std::shared_ptr<const SampledJointTrajectory> current_, goal_;
  double t0_s_, duration_s_;
  // Cubic coefficients per joint in s = (t - t0) / T: q = c0 + c1 s + c2 s^2 + c3 s^3.
  Joints c0_, c1_, c2_, c3_;
};

}  // namespace ephor::rambo
