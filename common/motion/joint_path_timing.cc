#include "common/motion/joint_path_timing.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ephor::arm {

JointPathTiming::JointPathTiming(const Puma560& arm, std::vector<Joints> waypoints,
                                 double tool_speed_cap_mm_s, double limit_fraction)
    : waypoints_(std::move(waypoints)) {
  if (waypoints_.empty()) throw std::invalid_argument("JointPathTiming: no waypoints");
  if (!(tool_speed_cap_mm_s > 0.0) || !(limit_fraction > 0.0) || limit_fraction > 1.0)
    throw std::invalid_argument(
        "JointPathTiming: need a tool speed cap > 0 and a limit fraction in (0, 1]");
  const JointLimits& lim = arm.limits();
  double t0 = 0.0;
  t_.push_back(0.0);
  s_.push_back(0.0);
  v_.push_back(0.0);
  segment_.push_back(0);
  for (std::size_t k = 0; k + 1 < waypoints_.size(); ++k) {
    const Joints delta = waypoints_[k + 1] - waypoints_[k];
    const double span = delta.cwiseAbs().maxCoeff();
    if (span < 1e-12) continue;
    double v_joint = 1e300, accel = 1e300;  // bounds on ds/dt and d2s/dt2
    for (int i = 0; i < 6; ++i) {
      const double d = std::abs(delta[i]);
      if (d < 1e-12) continue;
      v_joint = std::min(v_joint, limit_fraction * lim.qd_max[i] / d);
      accel = std::min(accel, limit_fraction * lim.qdd_max[i] / d);
    }
    const int n = std::max(20, static_cast<int>(std::ceil(span / 0.005)));
    const double ds = 1.0 / n;
    std::vector<double> vmax(static_cast<std::size_t>(n) + 1);
    auto tip = [&](double s) -> Eigen::Vector3d {
      const Joints q = waypoints_[k] + std::clamp(s, 0.0, 1.0) * delta;
      return arm.forward(q).translation();
    };
    for (int j = 0; j <= n; ++j) {
      const double s = j * ds;
      const double h = 0.5 * ds;
      const double dp_ds =
          (tip(s + h) - tip(s - h)).norm() / (std::min(1.0, s + h) - std::max(0.0, s - h));
      const double v_tool = dp_ds > 1e-9 ? 0.98 * tool_speed_cap_mm_s / dp_ds : 1e300;
      vmax[static_cast<std::size_t>(j)] = std::min(v_joint, v_tool);
    }
    std::vector<double> v(static_cast<std::size_t>(n) + 1, 0.0);
    for (int j = 1; j < n; ++j) {
      const auto u = static_cast<std::size_t>(j);
      v[u] = std::min(vmax[u], std::sqrt(v[u - 1] * v[u - 1] + 2.0 * accel * ds));
    }
    for (int j = n - 1; j > 0; --j) {
      const auto u = static_cast<std::size_t>(j);
      v[u] = std::min(v[u], std::sqrt(v[u + 1] * v[u + 1] + 2.0 * accel * ds));
    }
    double t = t0;
    for (int j = 1; j <= n; ++j) {
      const auto u = static_cast<std::size_t>(j);
      t += 2.0 * ds / (v[u - 1] + v[u]);  // constant acceleration between grid points
      t_.push_back(t);
      s_.push_back(j * ds);
      v_.push_back(v[u]);
      segment_.push_back(static_cast<int>(k));
    }
    t0 = t;
  }
}

Joints JointPathTiming::at(double t) const {
  if (t_.size() < 2 || t <= 0.0) return waypoints_.front();
  if (t >= t_.back()) return waypoints_.back();
  const auto it = std::upper_bound(t_.begin(), t_.end(), t);
  const auto j1 = static_cast<std::size_t>(it - t_.begin());
  const std::size_t j0 = j1 - 1;
  const auto k = static_cast<std::size_t>(segment_[j1]);
  // Grid point j0 may be the end of the previous segment: then it is s = 0 of this one.
  const double s0 = segment_[j0] == segment_[j1] ? s_[j0] : 0.0;
  const double v0 = segment_[j0] == segment_[j1] ? v_[j0] : 0.0;
  const double dt = t_[j1] - t_[j0];
  const double a = dt > 0.0 ? (v_[j1] - v0) / dt : 0.0;
  const double tau = t - t_[j0];
  const double s = std::clamp(s0 + v0 * tau + 0.5 * a * tau * tau, 0.0, 1.0);
  return waypoints_[k] + s * (waypoints_[k + 1] - waypoints_[k]);
}

}  // namespace ephor::arm
