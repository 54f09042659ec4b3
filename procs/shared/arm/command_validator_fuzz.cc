// Fuzz target (issue 18): an ARM_CMD message as ephor-arm handles it: the
// bytes decoded as arm_cmd_t the way the bus does (a message that does not
// decode to its full size is dropped), converted to an ArmCommand as main.cc
// does, and validated (CommandValidator) against the arm's joints: well-formed
// messages with NaN, infinities, unknown kinds and planes, huge or negative
// point counts, trajectories that break every limit. The motion planning that
// follows an accepted command (OMPL, up to its time budget) is not run here.
//
// The arm's current joints are its park joints; when the message's
// source_frame_utime is odd and it carries a trajectory with a finite first
// point, the arm is taken to be at that point, so the trajectory checks past
// the start are reached too.
//
// Seeds: fuzz_corpus/arm_command (one valid message of each kind).
#include <cstddef>
#include <cstdint>

#include "common/arm/arm_workcell.h"
#include "common/calibration/field_calibration.h"
#include "common/fuzz/fuzz_input.h"
#include "common/geometry/overhead_camera.h"
#include "common/geometry/workcell.h"
#include "ephor/arm_cmd_t.hpp"
#include "procs/shared/arm/command_validator.h"

namespace {

// As main.cc's handle_command.
ephor::arm::ArmCommand to_command(const ephor::arm_cmd_t& m) {
  ephor::arm::ArmCommand cmd;
  cmd.seq = m.seq;
  cmd.goal_id = m.goal_id;
  cmd.kind = m.kind;
  cmd.plane = m.plane;
  cmd.position_mm = Eigen::Vector3d(m.position_mm[0], m.position_mm[1], m.position_mm[2]);
  for (int j = 0; j < 6; ++j) cmd.joints[j] = m.joints_rad[j];
  cmd.u_px = static_cast<double>(m.u);
  cmd.v_px = static_cast<double>(m.v);
  cmd.theta_rad = static_cast<double>(m.theta_rad);
  cmd.max_speed_mm_s = static_cast<double>(m.max_speed_mm_s);
  if (m.kind == ephor::arm::kKindTrajectory) {
    for (std::size_t k = 0; k < m.traj_t_s.size(); ++k) {
      ephor::arm::TrajectoryPoint p;
      p.t_s = static_cast<double>(m.traj_t_s[k]);
      for (int j = 0; j < 6; ++j) {
        p.q[j] = m.traj_q_rad[k][static_cast<std::size_t>(j)];
        p.qd[j] = m.traj_qd_rad_s[k][static_cast<std::size_t>(j)];
      }
      cmd.trajectory.points.push_back(p);
    }
  }
  return cmd;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const ephor::geometry::Workcell cell;
  static const ephor::geometry::OverheadCamera camera;
  static const ephor::arm::CommandValidator validator(
      ephor::calibration::FieldCalibration::from_camera(camera, cell), cell);
  if (size > 1 << 20) return 0;  // larger than any LCM message the bus takes
  ephor::arm_cmd_t m;
  const int n = static_cast<int>(size);
  if (m.decode(data, 0, n) != n) return 0;
  const ephor::arm::ArmCommand cmd = to_command(m);
  ephor::arm::Joints current = ephor::arm::park_joints(cell);
  if ((m.source_frame_utime & 1) != 0 && !cmd.trajectory.points.empty() &&
      cmd.trajectory.points.front().q.allFinite())
    current = cmd.trajectory.points.front().q;
  const ephor::arm::Validation v = validator.validate(cmd, current);
  if (!v.ok && v.reason.empty()) ephor::fuzz::fail("a refused command carries no reason");
  if (v.ok && !(v.target.goal_q.allFinite() && v.target.speed_mm_s > 0.0 &&
                std::isfinite(v.target.speed_mm_s)))
    ephor::fuzz::fail("an accepted command has a non-finite goal or speed");
  return 0;
}
