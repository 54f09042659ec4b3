#include "common/rambo/reaching_trajectory.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ephor::rambo {

const char* to_string(ReachingMethod m) {
  return m == ReachingMethod::kCubicSpline ? "cubic" : "blend";
}

BlendValue blend_fraction(double s) {
  s = std::clamp(s, 0.0, 1.0);
  if (s <= 0.5) return {2.0 * s * s, 4.0 * s, 4.0};
  const double u = s - 1.0;
  return {1.0 - 2.0 * u * u, -4.0 * u, -4.0};
}

double blend_fraction_as_printed(double s) {
  s = std::clamp(s, 0.0, 1.0);
  if (s <= 0.5) return 2.0 * s * s * s * s;
  return 1.0 - 2.0 * (s - 1.0) * (s - 1.0);
}

ReachingTrajectory::ReachingTrajectory(ReachingMethod method,
                                       std::shared_ptr<const SampledJointTrajectory> current,
                                       std::shared_ptr<const SampledJointTrajectory> goal,
                                       double t0_s, double duration_s)
    : method_(method),
      current_(std::move(current)),
      goal_(std::move(goal)),
      t0_s_(t0_s),
      duration_s_(duration_s) {
  if (!current_ || !goal_) throw std::invalid_argument("ReachingTrajectory: missing trajectory");
  if (!std::isfinite(duration_s) || duration_s <= 0.0)
    throw std::invalid_argument("ReachingTrajectory: duration must be finite and > 0 s");
  if (!current_->covers(t0_s))
    throw std::invalid_argument("ReachingTrajectory: current trajectory does not cover t0");
  const double t1 = t0_s + duration_s;
  if (!goal_->covers(t1))
    throw std::invalid_argument("ReachingTrajectory: goal trajectory does not cover t0 + T");
  if (method_ == ReachingMethod::kBlend && (!goal_->covers(t0_s) || !current_->covers(t1)))
    throw std::invalid_argument(
        "ReachingTrajectory: blend needs both trajectories over [t0, t0 + T]");
  const JointSample a = current_->at(t0_s), b = goal_->at(t1);
  const double T = duration_s;
  // Hermite in s: end slopes are velocities times T.
  c0_ = a.q;
  c1_ = a.qd * T;
  c2_ = 3.0 * (b.q - a.q) - 2.0 * a.qd * T - b.qd * T;
  c3_ = -2.0 * (b.q - a.q) + a.qd * T + b.qd * T;
}

JointSample ReachingTrajectory::at(double t_s) const {
  if (t_s < t0_s_) return current_->at(t_s);
  if (t_s > t_land_s()) return goal_->at(t_s);
  const double T = duration_s_;
  const double s = (t_s - t0_s_) / T;
  JointSample r;
  if (method_ == ReachingMethod::kCubicSpline) {
    r.q = c0_ + s * (c1_ + s * (c2_ + s * c3_));
    r.qd = (c1_ + s * (2.0 * c2_ + 3.0 * s * c3_)) / T;
    r.qdd = (2.0 * c2_ + 6.0 * s * c3_) / (T * T);
    return r;
  }
  const JointSample p0 = current_->at(t_s), pg = goal_->at(t_s);
  const BlendValue f = blend_fraction(s);
  const double df = f.df / T, d2f = f.d2f / (T * T);
  r.q = f.f * pg.q + (1.0 - f.f) * p0.q;
  r.qd = df * (pg.q - p0.q) + f.f * pg.qd + (1.0 - f.f) * p0.qd;
  r.qdd = d2f * (pg.q - p0.q) + 2.0 * df * (pg.qd - p0.qd) + f.f * pg.qdd + (1.0 - f.f) * p0.qdd;
  return r;
}

}  // namespace ephor::rambo
