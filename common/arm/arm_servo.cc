#include "common/arm/arm_servo.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace ephor::sim {
namespace {

constexpr size_t kMaxPoints = 100000;
constexpr double kMaxDurationS = 3600.0;
// A trajectory's own points (their velocities, and the mean velocity and
// acceleration of each segment) must respect the limits to this slack...
constexpr double kPointSlack = 1.001;
// ...while the interpolated reference, checked every step, gets room for the
// cubic's own overshoot (a Hermite segment through an exact trapezoidal
// profile can ask up to 4/3 of the profile's acceleration).
constexpr double kVelocitySlack = 1.25;
constexpr double kAccelSlack = 1.5;

}  // namespace

std::optional<std::string> malformed(const JointTrajectory& t) {
  const size_t n = t.t_s.size();
  if (n == 0) return "trajectory has no points";
  if (n > kMaxPoints) return fmt::format("trajectory has {} points (max {})", n, kMaxPoints);
  if (t.q.size() != n || t.qd.size() != n)
    return fmt::format("trajectory has {} times but {} positions and {} velocities", n, t.q.size(),
                       t.qd.size());
  for (size_t i = 0; i < n; ++i) {
    if (!std::isfinite(t.t_s[i])) return fmt::format("t_s[{}] is not finite", i);
    if (!t.q[i].allFinite()) return fmt::format("q[{}] is not finite", i);
    if (!t.qd[i].allFinite()) return fmt::format("qd[{}] is not finite", i);
    if (i == 0 && t.t_s[0] < 0.0) return fmt::format("t_s[0] = {} s is negative", t.t_s[0]);
    if (i > 0 && !(t.t_s[i] > t.t_s[i - 1]))
      return fmt::format("t_s is not increasing at point {} ({} s after {} s)", i, t.t_s[i],
                         t.t_s[i - 1]);
  }
  if (t.t_s.back() > kMaxDurationS)
    return fmt::format("trajectory lasts {} s (max {} s)", t.t_s.back(), kMaxDurationS);
  return std::nullopt;
}

ArmServo::ArmServo(arm::JointLimits limits, const arm::Joints& start)
    : limits_(std::move(limits)), hold_(start) {
  if (!start.allFinite() || !limits_.within(start))
    throw std::invalid_argument("ArmServo: start joints are not finite or outside the limits");
  if (!(limits_.qd_max.array() > 0.0).all() || !(limits_.qdd_max.array() > 0.0).all())
    throw std::invalid_argument("ArmServo: velocity and acceleration limits must be > 0");
  state_.q = start;
}

void ArmServo::raise(const std::string& reason) {
  if (state_.fault) return;
  state_.fault = true;
  state_.fault_reason = reason;
}

void ArmServo::stop(const std::string& reason) {
  raise(reason);
  mode_ = Mode::kStop;
}

bool ArmServo::follow(const JointTrajectory& trajectory) {
  if (trajectory.seq == state_.trajectory_seq && state_.trajectory_seq != 0) return false;
  if (auto why = malformed(trajectory)) {
    state_.trajectory_seq = trajectory.seq;
    state_.trajectory_done = false;
    state_.fault = false;
    stop(fmt::format("trajectory {} refused: {}", trajectory.seq, *why));
    return false;
  }
  for (size_t i = 0; i < trajectory.q.size(); ++i) {
    for (int j = 0; j < 6; ++j) {
      const double qj = trajectory.q[i](j);
      if (qj < limits_.q_min(j) || qj > limits_.q_max(j)) {
        state_.trajectory_seq = trajectory.seq;
        state_.trajectory_done = false;
        state_.fault = false;
        stop(fmt::format(
            "trajectory {} refused: point {} puts joint {} at {:.3f} rad, outside [{:.3f}, {:.3f}]",
            trajectory.seq, i, j + 1, qj, limits_.q_min(j), limits_.q_max(j)));
        return false;
      }
    }
  }
  trajectory_ = JointTrajectory{};
  trajectory_.seq = trajectory.seq;
  if (trajectory.t_s.front() > 0.0) {
    trajectory_.t_s.push_back(0.0);
    trajectory_.q.push_back(state_.q);
    trajectory_.qd.push_back(state_.qd);
  }
  trajectory_.t_s.insert(trajectory_.t_s.end(), trajectory.t_s.begin(), trajectory.t_s.end());
  trajectory_.q.insert(trajectory_.q.end(), trajectory.q.begin(), trajectory.q.end());
  trajectory_.qd.insert(trajectory_.qd.end(), trajectory.qd.begin(), trajectory.qd.end());

  state_.trajectory_seq = trajectory.seq;
  state_.trajectory_done = false;
  state_.fault = false;
  state_.fault_reason.clear();
  mode_ = Mode::kFollow;
  t_ = 0.0;
  previous_ref_velocity_.reset();

  check_points();
  const arm::Joints jump = (trajectory_.q.front() - state_.q).cwiseAbs();
  int j = 0;
  if (jump.maxCoeff(&j) > start_tolerance_rad)
    raise(fmt::format("trajectory {} starts {:.3f} rad away from joint {}'s position",
                      trajectory.seq, jump(j), j + 1));
  return true;
}

void ArmServo::check_points() {
  const auto& ts = trajectory_.t_s;
  for (size_t i = 0; i < ts.size(); ++i) {
    for (int j = 0; j < 6; ++j) {
      const double vmax = kPointSlack * limits_.qd_max(j), amax = kPointSlack * limits_.qdd_max(j);
      const double v = trajectory_.qd[i](j);
      if (std::abs(v) > vmax)
        return raise(
            fmt::format("trajectory {} asks joint {} for {:.3f} rad/s at t = {:.3f} s "
                        "(velocity limit {:.3f} rad/s); clamped",
                        trajectory_.seq, j + 1, v, ts[i], limits_.qd_max(j)));
      if (i == 0) continue;
      const double dt = ts[i] - ts[i - 1];
      const double v_mean = (trajectory_.q[i](j) - trajectory_.q[i - 1](j)) / dt;
      if (std::abs(v_mean) > vmax)
        return raise(fmt::format(
            "trajectory {} moves joint {} at {:.3f} rad/s between t = {:.3f} and {:.3f} s "
            "(velocity limit {:.3f} rad/s); clamped",
            trajectory_.seq, j + 1, v_mean, ts[i - 1], ts[i], limits_.qd_max(j)));
      const double a_mean = (trajectory_.qd[i](j) - trajectory_.qd[i - 1](j)) / dt;
      if (std::abs(a_mean) > amax)
        return raise(fmt::format(
            "trajectory {} accelerates joint {} at {:.3f} rad/s^2 between t = {:.3f} and {:.3f} s "
            "(acceleration limit {:.3f} rad/s^2); clamped",
            trajectory_.seq, j + 1, a_mean, ts[i - 1], ts[i], limits_.qdd_max(j)));
    }
  }
}

arm::Joints ArmServo::reference(double t) const {
  const auto& ts = trajectory_.t_s;
  if (t <= ts.front()) return trajectory_.q.front();
  if (t >= ts.back()) return trajectory_.q.back();
  const size_t i = static_cast<size_t>(std::upper_bound(ts.begin(), ts.end(), t) - ts.begin()) - 1;
  const double h = ts[i + 1] - ts[i];
  const double s = (t - ts[i]) / h;
  const double s2 = s * s, s3 = s2 * s;
  // Cubic Hermite basis.
  const double h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2,
               h11 = s3 - s2;
  return h00 * trajectory_.q[i] + h10 * h * trajectory_.qd[i] + h01 * trajectory_.q[i + 1] +
         h11 * h * trajectory_.qd[i + 1];
}

void ArmServo::step(double dt_s) {
  if (!std::isfinite(dt_s) || dt_s <= 0.0)
    throw std::invalid_argument(
        fmt::format("ArmServo::step: dt must be finite and > 0, got {}", dt_s));
  arm::Joints v_des = arm::Joints::Zero();
  if (mode_ == Mode::kFollow || mode_ == Mode::kHold) {
    arm::Joints ref_now = hold_, ref_next = hold_;
    if (mode_ == Mode::kFollow) {
      ref_now = reference(t_);
      ref_next = reference(t_ + dt_s);
    }
    const arm::Joints v_ref = (ref_next - ref_now) / dt_s;
    // Only the first fault's reason is kept (raise()): once one is latched
    // the checks below are skipped, since formatting a reason at every step
    // (a 130-digit velocity of a trajectory asking 1e131 rad/s, 12 a step)
    // made one simulated millisecond cost a fifth of a real one.
    if (mode_ == Mode::kFollow && !state_.fault) {
      for (int j = 0; j < 6; ++j) {
        if (std::abs(v_ref(j)) > kVelocitySlack * limits_.qd_max(j))
          raise(
              fmt::format("trajectory {} demands joint {} velocity {:.3f} rad/s at t = {:.3f} s "
                          "(limit {:.3f} rad/s); clamped",
                          trajectory_.seq, j + 1, v_ref(j), t_, limits_.qd_max(j)));
        if (previous_ref_velocity_) {
          const double a = (v_ref(j) - (*previous_ref_velocity_)(j)) / dt_s;
          if (std::abs(a) > kAccelSlack * limits_.qdd_max(j))
            raise(fmt::format(
                "trajectory {} demands joint {} acceleration {:.3f} rad/s^2 at t = {:.3f} s "
                "(limit {:.3f} rad/s^2); clamped",
                trajectory_.seq, j + 1, a, t_, limits_.qdd_max(j)));
        }
      }
      previous_ref_velocity_ = v_ref;
    }
    // Land on the reference; when lagging, catch up no faster than the joint
    // can still brake from.
    for (int j = 0; j < 6; ++j) {
      const double lag = ref_now(j) - state_.q(j);
      const double catch_up =
          std::min(std::abs(lag) / dt_s, std::sqrt(2.0 * limits_.qdd_max(j) * std::abs(lag)));
      v_des(j) = v_ref(j) + std::copysign(catch_up, lag);
    }
  }
  // kStop: v_des stays zero, so the joints brake at qdd_max.

  arm::Joints v;
  for (int j = 0; j < 6; ++j) {
    const double vj = std::clamp(v_des(j), -limits_.qd_max(j), limits_.qd_max(j));
    const double dv = limits_.qdd_max(j) * dt_s;
    v(j) = std::clamp(vj, state_.qd(j) - dv, state_.qd(j) + dv);
  }
  arm::Joints q = state_.q + v * dt_s;
  for (int j = 0; j < 6; ++j) {
    if (q(j) < limits_.q_min(j) || q(j) > limits_.q_max(j)) {
      // Hard stop at the limit (the real arm would hit its end stop).
      q(j) = std::clamp(q(j), limits_.q_min(j), limits_.q_max(j));
      v(j) = 0.0;
      stop(fmt::format("joint {} reached its position limit ({:.3f} rad)", j + 1, q(j)));
    }
  }
  state_.q = q;
  state_.qd = v;
  t_ += dt_s;

  if (mode_ == Mode::kStop && state_.qd.isZero()) {
    hold_ = state_.q;
    mode_ = Mode::kHold;
  }
  if (mode_ == Mode::kFollow && t_ >= trajectory_.t_s.back() &&
      (state_.q - trajectory_.q.back()).cwiseAbs().maxCoeff() <= done_tolerance_rad) {
    state_.trajectory_done = true;
    hold_ = trajectory_.q.back();
    mode_ = Mode::kHold;
  }
}

}  // namespace ephor::sim
