#include "common/arm/servo_messages.h"

#include <Eigen/Core>

namespace ephor::sim {

std::optional<JointTrajectory> to_trajectory(const joint_trajectory_t& m, std::string& why) {
  const size_t n = m.num_points < 0 ? 0 : static_cast<size_t>(m.num_points);
  if (m.num_points <= 0 || m.t_s.size() != n || m.q.size() != n || m.qd.size() != n) {
    why = "num_points " + std::to_string(m.num_points) + " does not match the arrays";
    return std::nullopt;
  }
  JointTrajectory t;
  t.seq = m.seq;
  for (size_t i = 0; i < n; ++i) {
    if (m.q[i].size() != 6 || m.qd[i].size() != 6) {
      why = "point " + std::to_string(i) + " does not have 6 joints";
      return std::nullopt;
    }
    t.t_s.push_back(static_cast<double>(m.t_s[i]));
    t.q.push_back(Eigen::Map<const arm::Joints>(m.q[i].data()));
    t.qd.push_back(Eigen::Map<const arm::Joints>(m.qd[i].data()));
  }
  if (auto bad = malformed(t)) {
    why = *bad;
    return std::nullopt;
  }
  return t;
}

joint_state_t to_joint_state(const ServoState& s, int64_t utime) {
  joint_state_t m;
  m.utime = utime;
  for (int j = 0; j < 6; ++j) {
    m.q[j] = s.q(j);
    m.qd[j] = s.qd(j);
  }
  m.trajectory_seq = s.trajectory_seq;
  m.trajectory_done = s.trajectory_done;
  m.fault = s.fault;
  m.fault_reason = s.fault_reason;
  return m;
}

}  // namespace ephor::sim
