#include "common/shepherd/calibrate/joint_move.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ephor::calibrate {

namespace {

// Normalised trapezoid s(t/T) in [0, 1] over [0, 1]: acceleration 4.5 for
// the first third, cruise at 1.5, braking in the last third. Returns (s, ds/dx).
std::pair<double, double> profile(double x) {
  constexpr double a = 4.5, third = 1.0 / 3.0;
  if (x <= third) return {0.5 * a * x * x, a * x};
  if (x <= 2.0 * third) return {0.25 + 1.5 * (x - third), 1.5};
  const double r = 1.0 - x;
  return {1.0 - 0.5 * a * r * r, a * r};
}

}  // namespace

JointPath JointMove::plan(const arm::Joints& from, const arm::Joints& to,
                          const arm::JointLimits& limits, double speed_fraction, double sample_s) {
  if (!from.allFinite() || !to.allFinite())
    throw std::invalid_argument("JointMove: joints are not finite");
  if (!limits.within(from, 1e-6) || !limits.within(to, 1e-6))
    throw std::invalid_argument("JointMove: start or goal outside the joint limits");
  if (!(speed_fraction > 0.0 && speed_fraction <= 1.0))
    throw std::invalid_argument("JointMove: speed_fraction must be in (0, 1]");
  if (!(sample_s > 0.0 && std::isfinite(sample_s)))
    throw std::invalid_argument("JointMove: sample_s must be finite and > 0");

  const arm::Joints dq = to - from;
  // Peak velocity 1.5 |dq| / T and acceleration 4.5 |dq| / T^2 within the fraction of the limits.
  double T = 0.2;
  for (int j = 0; j < 6; ++j) {
    const double d = std::abs(dq(j));
    T = std::max(T, 1.5 * d / (speed_fraction * limits.qd_max(j)));
    T = std::max(T, std::sqrt(4.5 * d / (speed_fraction * limits.qdd_max(j))));
  }
  const int n = std::max(2, static_cast<int>(std::ceil(T / sample_s)));
  JointPath p;
  for (int k = 0; k <= n; ++k) {
    const double x = static_cast<double>(k) / n;
    const auto [s, ds] = profile(x);
    p.t_s.push_back(x * T);
    p.q.push_back(k == n ? to : arm::Joints(from + s * dq));
    p.qd.push_back(k == n ? arm::Joints::Zero() : arm::Joints(dq * (ds / T)));
  }
  return p;
}

}  // namespace ephor::calibrate
