#include "common/rambo/joint_trajectory.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace ephor::rambo {

SampledJointTrajectory::SampledJointTrajectory(double t0_s, double dt_s,
                                               std::vector<JointSample> samples)
    : t0_s_(t0_s), dt_s_(dt_s), samples_(std::move(samples)) {
  if (!std::isfinite(t0_s) || !std::isfinite(dt_s) || dt_s <= 0.0)
    throw std::invalid_argument("SampledJointTrajectory: t0 and dt must be finite, dt > 0 s");
  if (samples_.empty()) throw std::invalid_argument("SampledJointTrajectory: no samples");
  for (const auto& s : samples_) {
    if (!s.q.allFinite() || !s.qd.allFinite() || !s.qdd.allFinite())
      throw std::invalid_argument("SampledJointTrajectory: a sample is not finite");
  }
}

SampledJointTrajectory SampledJointTrajectory::from_positions(double t0_s, double dt_s,
                                                              const std::vector<Joints>& q) {
  if (q.size() < 3) throw std::invalid_argument("SampledJointTrajectory: needs >= 3 positions");
  const std::size_t n = q.size();
  std::vector<JointSample> s(n);
  for (std::size_t k = 0; k < n; ++k) {
    s[k].q = q[k];
    const std::size_t a = k == 0 ? 0 : (k == n - 1 ? n - 3 : k - 1);
    // Three consecutive samples a, a+1, a+2; derivatives of their parabola at k.
    const double x = (static_cast<double>(k) - static_cast<double>(a) - 1.0);  // -1, 0 or 1
    const Joints d1 = (q[a + 2] - q[a]) / (2.0 * dt_s);
    const Joints d2 = (q[a + 2] - 2.0 * q[a + 1] + q[a]) / (dt_s * dt_s);
    s[k].qd = d1 + d2 * (x * dt_s);
    s[k].qdd = d2;
  }
  return SampledJointTrajectory(t0_s, dt_s, std::move(s));
}

SampledJointTrajectory SampledJointTrajectory::from_function(
    double t0_s, double dt_s, int n, const std::function<JointSample(double)>& fn) {
  std::vector<JointSample> s;
  s.reserve(static_cast<std::size_t>(std::max(n, 0)));
  for (int k = 0; k < n; ++k) s.push_back(fn(t0_s + dt_s * k));
  return SampledJointTrajectory(t0_s, dt_s, std::move(s));
}

JointSample SampledJointTrajectory::at(double t_s) const {
  if (samples_.size() == 1) return samples_[0];
  const double u = std::clamp((t_s - t0_s_) / dt_s_, 0.0, static_cast<double>(samples_.size() - 1));
  const std::size_t k = std::min(static_cast<std::size_t>(u), samples_.size() - 2);
  const double s = u - static_cast<double>(k);
  const JointSample& a = samples_[k];
  const JointSample& b = samples_[k + 1];
  const double s2 = s * s, s3 = s2 * s;
  JointSample r;
  r.q = (2 * s3 - 3 * s2 + 1) * a.q + (s3 - 2 * s2 + s) * dt_s_ * a.qd + (-2 * s3 + 3 * s2) * b.q +
        (s3 - s2) * dt_s_ * b.qd;
  r.qd = (1 - s) * a.qd + s * b.qd;
  r.qdd = (1 - s) * a.qdd + s * b.qdd;
  return r;
}

std::optional<SampledJointTrajectory> joint_trajectory_from_poses(
    const arm::Puma560& arm, const std::function<Eigen::Isometry3d(double)>& tool_pose,
    const Joints& start_near, double t0_s, double dt_s, int n, std::string* why,
    double max_step_rad, bool partial) {
  std::vector<Joints> q;
  q.reserve(static_cast<std::size_t>(std::max(n, 0)));
  Joints prev = start_near;
  for (int k = 0; k < n; ++k) {
    const double t = t0_s + dt_s * k;
    const auto sol = arm.nearest_inverse(tool_pose(t), prev);
    if (!sol) {
      if (why) {
        std::ostringstream o;
        o << "goal pose out of reach at t = " << t << " s";
        *why = o.str();
      }
      if (partial) break;
      return std::nullopt;
    }
    if (k > 0 && (*sol - prev).cwiseAbs().maxCoeff() > max_step_rad) {
      if (why) {
        std::ostringstream o;
        o << "inverse kinematics changes branch at t = " << t << " s";
        *why = o.str();
      }
      if (partial) break;
      return std::nullopt;
    }
    q.push_back(*sol);
    prev = *sol;
  }
  if (q.size() < 3) {
    if (why && why->empty()) *why = "fewer than 3 samples";
    return std::nullopt;
  }
  return SampledJointTrajectory::from_positions(t0_s, dt_s, q);
}

}  // namespace ephor::rambo
