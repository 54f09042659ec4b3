#pragma once
// Whether the chaser captured the sphere (issue 15): when the sphere's
// centre reaches the capture distance along the boresight (Z = 1 m), the
// relative speed must be below 2 cm/s and the centre within 2 cm of the
// boresight axis (the capture mechanism's axis).

#include <optional>
#include <string>

#include "common/sphere/sphere_trajectory.h"

namespace ephor::sphere {

struct CaptureCriteria {
  double capture_distance_m = 1.0;  // Z of the centre at capture
  double max_speed_m_s = 0.02;      // |relative velocity|
  double max_offset_m = 0.02;       // hypot(X, Y) of the centre
};

struct CaptureVerdict {
  bool captured = false;
  double t_s = 0.0;  // when the centre reached the capture distance
  double speed_m_s = 0.0;
  double offset_m = 0.0;
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity_m_s = Eigen::Vector3d::Zero();
  std::string text;  // "captured: ..." or "not captured: ..." with the numbers
};

class CaptureJudge {
 public:
  explicit CaptureJudge(const CaptureCriteria& criteria = {}) : criteria_(criteria) {}

  // The verdict if the centre, moving linearly along `motion`, reaches the
  // capture distance during (t0_s, t1_s] (or is already inside it at t0_s).
  std::optional<CaptureVerdict> judge(const SphereTrajectory& motion, double t0_s,
                                      double t1_s) const;

  // "not captured: gave up after ..." at t_s.
  CaptureVerdict give_up(const SphereTrajectory& motion, double t_s) const;

  const CaptureCriteria& criteria() const { return criteria_; }

 private:
  CaptureVerdict verdict_at(const SphereTrajectory& motion, double t_s) const;
  CaptureCriteria criteria_;
};

}  // namespace ephor::sphere
