#pragma once
// ArmServo: the PUMA 560's servo layer - RCCL on the paper's Sparcstation
// (paper 003, sections 3.6 and 5), simulated. It holds the joint state, follows
// the newest joint trajectory by interpolating its points in time, and never
// moves a joint faster, harder or farther than the limits allow.
//
// Units: rad, rad/s, rad/s^2, s; PUMA 560 joint order (common/arm/puma560.h).
//
// Following: between two points the reference is the cubic Hermite curve
// through their positions and velocities; before the first point (if its time
// is > 0) it starts from the state at acceptance; after the last it holds the
// last position. Each step commands the velocity that lands on the reference
// (plus a catch-up term, bounded so the joint can still brake, when it lags),
// then clamps it to qd_max and the change to qdd_max * dt. So the limits hold
// whatever a trajectory asks.
//
// Faults (latched until the next accepted trajectory; the first reason wins):
// - a point outside [q_min, q_max]: the trajectory is refused and the arm
//   brakes to a stop at qdd_max and holds there;
// - the trajectory itself asks for more than the limits - a point's velocity,
//   or a segment's mean velocity (dq / dt) or mean acceleration (dqd / dt),
//   above qd_max or qdd_max; or the interpolated reference grossly so (25 %
//   over qd_max, 50 % over qdd_max: room for the cubic's own overshoot); or
//   it starts away from the arm (> start_tolerance_rad): the arm keeps
//   following, clamped, and reports the fault with the reason.
// - a joint reaching its position limit while following: stop, as above.
//
// A trajectory with the seq being followed is a duplicate and is ignored;
// any other seq replaces the current trajectory at once ("newest wins").
//
// Threading: not thread-safe; one owner calls everything.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common/arm/puma560.h"

namespace ephor::sim {

// A time-parameterised joint trajectory (joint_trajectory_t in struct form).
struct JointTrajectory {
  int64_t seq = 0;
  std::vector<double> t_s;      // from the start of execution, s, strictly increasing, >= 0
  std::vector<arm::Joints> q;   // rad
  std::vector<arm::Joints> qd;  // rad/s
};

// Why a trajectory is malformed (sizes, finiteness, time order, duration), or
// nullopt when it is well formed. Limits are not checked here.
std::optional<std::string> malformed(const JointTrajectory& trajectory);

struct ServoState {
  arm::Joints q = arm::Joints::Zero();   // rad
  arm::Joints qd = arm::Joints::Zero();  // rad/s
  int64_t trajectory_seq = 0;            // being (or last) executed; 0 = none yet
  bool trajectory_done = true;           // the last point of trajectory_seq was reached
  bool fault = false;
  std::string fault_reason;
};

class ArmServo {
 public:
  // Starts at rest at `start` (which must be within the limits).
  ArmServo(arm::JointLimits limits, const arm::Joints& start);

  // Takes a new trajectory from the next step on. Returns false when it was
  // ignored (duplicate seq) or refused (malformed, out of the position
  // limits: the arm then stops and the state carries the fault).
  bool follow(const JointTrajectory& trajectory);
  // Brakes to a stop at qdd_max and holds (an e-stop), with a fault.
  void stop(const std::string& reason);

  // Advances by dt_s (> 0, finite) seconds.
  void step(double dt_s);

  const ServoState& state() const { return state_; }
  const arm::JointLimits& limits() const { return limits_; }

  double start_tolerance_rad = 0.05;  // see the fault list above
  double done_tolerance_rad = 1e-3;

 private:
  enum class Mode { kHold, kFollow, kStop };
  arm::Joints reference(double t) const;
  void raise(const std::string& reason);
  void check_points();

  arm::JointLimits limits_;
  ServoState state_;
  Mode mode_ = Mode::kHold;
  arm::Joints hold_;
  JointTrajectory trajectory_;  // with the start state prepended when t_s[0] > 0
  double t_ = 0.0;              // time since the trajectory started, s
  std::optional<arm::Joints> previous_ref_velocity_;
};

}  // namespace ephor::sim
