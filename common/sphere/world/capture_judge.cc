#include "common/sphere/world/capture_judge.h"

#include <cmath>

#include <fmt/format.h>

namespace ephor::sphere {

CaptureVerdict CaptureJudge::verdict_at(const SphereTrajectory& motion, double t_s) const {
  CaptureVerdict v;
  v.t_s = t_s;
  v.position_m = motion.centre_at(t_s);
  v.velocity_m_s = motion.velocity_m_s;
  v.speed_m_s = v.velocity_m_s.norm();
  v.offset_m = std::hypot(v.position_m.x(), v.position_m.y());
  const bool slow = v.speed_m_s < criteria_.max_speed_m_s;
  const bool centred = v.offset_m < criteria_.max_offset_m;
  v.captured = slow && centred;
  std::string why;
  if (!slow) why += fmt::format(" too fast (limit {:.1f} cm/s)", criteria_.max_speed_m_s * 100);
  if (!centred) why += fmt::format(" off the axis (limit {:.1f} cm)", criteria_.max_offset_m * 100);
  v.text = fmt::format(
      "{} at t = {:.2f} s: relative speed {:.2f} cm/s, offset {:.2f} cm from the axis (centre "
      "{:.3f}, {:.3f}, {:.3f} m; velocity {:.2f}, {:.2f}, {:.2f} cm/s){}",
      v.captured ? "captured" : "not captured", t_s, v.speed_m_s * 100, v.offset_m * 100,
      v.position_m.x(), v.position_m.y(), v.position_m.z(), v.velocity_m_s.x() * 100,
      v.velocity_m_s.y() * 100, v.velocity_m_s.z() * 100, v.captured ? "" : ":" + why);
  return v;
}

std::optional<CaptureVerdict> CaptureJudge::judge(const SphereTrajectory& motion, double t0_s,
                                                  double t1_s) const {
  const double d = criteria_.capture_distance_m;
  const double z0 = motion.centre_at(t0_s).z();
  if (z0 <= d) return verdict_at(motion, t0_s);
  const double vz = motion.velocity_m_s.z();
  if (!(vz < 0.0)) return std::nullopt;
  const double t = t0_s + (d - z0) / vz;  // z(t) = d
  if (t > t1_s) return std::nullopt;
  return verdict_at(motion, t);
}

CaptureVerdict CaptureJudge::give_up(const SphereTrajectory& motion, double t_s) const {
  CaptureVerdict v = verdict_at(motion, t_s);
  v.captured = false;
  const Eigen::Vector3d p = motion.centre_at(t_s);
  v.text = fmt::format(
      "not captured: gave up after {:.1f} s with the centre at ({:.3f}, {:.3f}, {:.3f}) m, "
      "relative speed {:.2f} cm/s",
      t_s, p.x(), p.y(), p.z(), v.speed_m_s * 100);
  return v;
}

}  // namespace ephor::sphere
