#pragma once
// ToolLine: the straight motion of the PUMA's tool between two poses (base
// frame, mm): position linear, orientation by slerp. follow() walks it as
// ephor-arm executes a Cartesian move, taking at each sample the
// inverse-kinematics solution nearest the previous one, and says where that
// breaks: a sample out of reach, or a jump of the joints (a change of IK
// branch, a joint limit, a singularity).
//
// Shared by ephor-arm (MotionPlanner: is the straight line feasible?) and
// the planner (ArmConfiguration: will the arm take a joint-space path?), so
// that both judge a line the same way. Pure kinematics, no LCM.

#include <functional>
#include <optional>

#include <Eigen/Geometry>

#include "common/arm/puma560.h"

namespace ephor::arm {

// Where and why a walk along a ToolLine stopped before its end.
struct LineBreak {
  enum class Kind { kUnreachable, kJump, kRejected };
  Kind kind = Kind::kUnreachable;
  double u = 0.0;         // fraction of the line (0..1] at the failing sample
  double jump_rad = 0.0;  // kJump: the largest joint change between the two samples, rad
};

class ToolLine {
 public:
  ToolLine(const Eigen::Isometry3d& from, const Eigen::Isometry3d& to);

  // The pose at fraction u of the line (clamped to [0, 1]).
  Eigen::Isometry3d at(double u) const;
  double length_mm() const { return length_mm_; }
  double angle_rad() const { return angle_rad_; }

  // Walks the line from joints `start` in `samples` equal steps. At each
  // sample: the IK solution nearest the previous joints; a break when there
  // is none, when a joint changes by more than max_jump_rad, or when
  // `accept` (if given) returns false for the sample's joints. `end` gets
  // the joints of the last sample reached.
  std::optional<LineBreak> follow(const Puma560& arm, const Joints& start, int samples,
                                  double max_jump_rad,
                                  const std::function<bool(const Joints&)>& accept = {},
                                  Joints* end = nullptr) const;

 private:
  Eigen::Vector3d p0_, p1_;
  Eigen::Quaterniond r0_, r1_;
  double length_mm_ = 0.0;
  double angle_rad_ = 0.0;
};

}  // namespace ephor::arm
