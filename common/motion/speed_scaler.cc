#include "common/motion/speed_scaler.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace ephor::arm {

namespace {
// ephor-sim's servo checks the interpolated reference against 1.5 x the
// acceleration limit (common/arm/arm_servo.cc); its 4 ms differences of the
// cubic see a little more than the cubic's own end accelerations.
constexpr double kHermiteAccelSlack = 1.45;
}  // namespace

SpeedScaler::SpeedScaler(const Puma560& arm, ScalingConfig config) : arm_(arm), config_(config) {}

ScaledTrajectory SpeedScaler::sample(const TimedPath& path, double nominal_duration_s,
                                     const Joints& start, double stretch) const {
  ScaledTrajectory out;
  out.stretch = stretch;
  const double total = nominal_duration_s * stretch;
  const int n = std::max(1, static_cast<int>(std::ceil(total / config_.sample_period_s - 1e-9)));
  const double dt = total / n;
  std::vector<TrajectoryPoint>& pts = out.trajectory.points;
  pts.resize(static_cast<std::size_t>(n) + 1);
  Joints previous = start;
  for (int j = 0; j <= n; ++j) {
    std::string why;
    const auto q = path(j * dt / stretch, previous, &why);
    if (!q) {
      out.reason = why.empty() ? "path cannot be followed" : why;
      return out;
    }
    pts[static_cast<std::size_t>(j)].t_s = j * dt;
    pts[static_cast<std::size_t>(j)].q = *q;
    previous = *q;
  }
  out.ok = true;
  if (total <= 0.0) {
    pts.resize(1);
    return out;
  }
  // Finite differences; the motion starts and ends at rest.
  const auto q_at = [&](int j) -> const Joints& { return pts[static_cast<std::size_t>(j)].q; };
  const JointLimits& lim = arm_.limits();
  Eigen::Vector3d tip_prev = arm_.forward(q_at(0)).translation();
  for (int j = 0; j <= n; ++j) {
    Joints qd = Joints::Zero();
    Joints qdd;
    if (j == 0) {
      qdd = 2.0 * (q_at(1) - q_at(0)) / (dt * dt);
    } else if (j == n) {
      qdd = 2.0 * (q_at(n - 1) - q_at(n)) / (dt * dt);
    } else {
      qd = (q_at(j + 1) - q_at(j - 1)) / (2.0 * dt);
      qdd = (q_at(j + 1) - 2.0 * q_at(j) + q_at(j - 1)) / (dt * dt);
    }
    pts[static_cast<std::size_t>(j)].qd = qd;
    out.velocity_ratio =
        std::max(out.velocity_ratio, (qd.array().abs() / lim.qd_max.array()).maxCoeff());
    out.acceleration_ratio =
        std::max(out.acceleration_ratio, (qdd.array().abs() / lim.qdd_max.array()).maxCoeff());
    if (j > 0) {
      // The servo follows the cubic Hermite curve through the points and
      // their velocities, whose acceleration at a segment's ends overshoots
      // the finite difference where the motion turns sharply (up to 1.5 x at
      // the peak of a short move's triangular profile). It allows the
      // interpolated reference kHermiteAccelSlack x the limit: check it.
      const Joints& v0 = pts[static_cast<std::size_t>(j - 1)].qd;
      const Joints dq = q_at(j) - q_at(j - 1);
      const Joints a_start = (6.0 * dq / dt - 4.0 * v0 - 2.0 * qd) / dt;
      const Joints a_end = (-6.0 * dq / dt + 2.0 * v0 + 4.0 * qd) / dt;
      const double hermite = std::max((a_start.array().abs() / lim.qdd_max.array()).maxCoeff(),
                                      (a_end.array().abs() / lim.qdd_max.array()).maxCoeff());
      out.acceleration_ratio = std::max(out.acceleration_ratio, hermite / kHermiteAccelSlack);
      const Eigen::Vector3d tip = arm_.forward(q_at(j)).translation();
      out.peak_tool_speed_mm_s = std::max(out.peak_tool_speed_mm_s, (tip - tip_prev).norm() / dt);
      tip_prev = tip;
    }
  }
  return out;
}

ScaledTrajectory SpeedScaler::scale(const TimedPath& path, double nominal_duration_s,
                                    const Joints& start) const {
  double stretch = 1.0;
  ScaledTrajectory result;
  for (int pass = 0; pass < config_.max_passes; ++pass) {
    result = sample(path, nominal_duration_s, start, stretch);
    if (!result.ok || nominal_duration_s <= 0.0) return result;
    const double need = std::max({result.velocity_ratio / config_.limit_fraction,
                                  std::sqrt(result.acceleration_ratio / config_.limit_fraction),
                                  result.peak_tool_speed_mm_s / config_.max_tool_speed_mm_s});
    if (need <= 1.0) return result;
    stretch *= std::max(need / config_.target_ratio, 1.01);
    if (stretch > config_.max_stretch) break;
  }
  result.ok = false;
  char buf[200];
  std::snprintf(buf, sizeof buf,
                "joint speeds stay above their limits even slowed down %.0f times "
                "(velocity ratio %.2f, acceleration ratio %.2f): the path passes a singularity",
                stretch, result.velocity_ratio, result.acceleration_ratio);
  result.reason = buf;
  return result;
}

}  // namespace ephor::arm
