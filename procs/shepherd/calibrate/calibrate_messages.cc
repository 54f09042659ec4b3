#include "procs/shepherd/calibrate/calibrate_messages.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include <fmt/format.h>

namespace ephor::calibrate {

bool CellInputs::on_frame(const camera_frame_t& m) {
  if (m.width <= 0 || m.height <= 0 ||
      m.data.size() != static_cast<size_t>(m.width) * static_cast<size_t>(m.height)) {
    ++bad_frames_;
    return false;
  }
  std::lock_guard<std::mutex> lock(mutex_);
  frame_ = m;
  frame_utime_ = m.utime;
  return true;
}

bool CellInputs::on_state(const joint_state_t& m) {
  for (double q : m.q)
    if (!std::isfinite(q)) return false;
  std::lock_guard<std::mutex> lock(mutex_);
  state_ = m;
  return true;
}

std::optional<joint_state_t> CellInputs::state() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return state_;
}

GreyFrame CellInputs::frame() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return {frame_.width, frame_.height,
          std::vector<uint8_t>(frame_.data.begin(), frame_.data.end())};
}

arm::Joints joints_of(const joint_state_t& s) { return Eigen::Map<const arm::Joints>(s.q); }

arm::Joints move_start_of(const joint_state_t& s, const arm::JointLimits& limits) {
  constexpr double kToleranceRad = 1e-6;  // JointMove::plan's
  arm::Joints q = joints_of(s);
  for (int j = 0; j < 6; ++j) {
    if (!std::isfinite(q(j)) || q(j) < limits.q_min(j) - kToleranceRad ||
        q(j) > limits.q_max(j) + kToleranceRad)
      throw std::runtime_error(
          fmt::format("the servo reports joint {} at {} rad, outside its limits [{:.3f}, {:.3f}]",
                      j + 1, q(j), limits.q_min(j), limits.q_max(j)));
    q(j) = std::clamp(q(j), limits.q_min(j), limits.q_max(j));
  }
  return q;
}

joint_trajectory_t trajectory_message_of(const JointPath& path, int64_t utime, int64_t seq) {
  joint_trajectory_t m;
  m.utime = utime;
  m.seq = seq;
  m.num_points = static_cast<int32_t>(path.t_s.size());
  for (size_t i = 0; i < path.t_s.size(); ++i) {
    m.t_s.push_back(static_cast<float>(path.t_s[i]));
    m.q.emplace_back(path.q[i].data(), path.q[i].data() + 6);
    m.qd.emplace_back(path.qd[i].data(), path.qd[i].data() + 6);
  }
  return m;
}

}  // namespace ephor::calibrate
