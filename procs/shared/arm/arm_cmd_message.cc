#include "procs/shared/arm/arm_cmd_message.h"

#include <cstddef>

namespace ephor::arm {

ArmCommand command_from_message(const arm_cmd_t& m) {
  ArmCommand cmd;
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
  if (m.kind == kKindTrajectory) {
    for (std::size_t k = 0; k < m.traj_t_s.size(); ++k) {
      TrajectoryPoint p;
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

}  // namespace ephor::arm
