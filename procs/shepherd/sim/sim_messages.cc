#include "procs/shepherd/sim/sim_messages.h"

#include <string>
#include <utility>

#include <spdlog/spdlog.h>

#include "common/arm/servo_messages.h"

namespace ephor::sim {

std::optional<JointTrajectory> SimInputs::on_trajectory(const joint_trajectory_t& m) {
  ++trajectories_received_;
  std::string why;
  auto t = to_trajectory(m, why);
  if (!t) {
    ++trajectories_refused_;
    spdlog::warn("ARM_TRAJECTORY seq {} ignored: {} ({} ignored so far)", m.seq, why,
                 trajectories_refused_.load());
  }
  return t;
}

bool SimInputs::on_command(const shepherd_sim_cmd_t& m, Simulator& sim) {
  if (m.sheep < 0 || m.sheep > kMaxSheep) {
    ++commands_refused_;
    spdlog::warn("SIM_CMD ignored: sheep {} outside [0, {}]", m.sheep, kMaxSheep);
    return false;
  }
  const bool reset = m.reset && (!last_reset_ || m.seed != last_seed_);
  last_reset_ = m.reset;
  last_seed_ = m.seed;
  if (reset) {
    sim.reset(static_cast<uint64_t>(m.seed));
    last_sheep_ = -1;
    spdlog::info("world reset with seed {}", m.seed);
  }
  if (m.sheep != last_sheep_) {
    sim.world().set_sheep_count(m.sheep);
    last_sheep_ = m.sheep;
  }
  return true;
}

void SimInputs::on_tool_light(const shepherd_tool_light_t& m, Simulator& sim) {
  if (sim.tool_light() != m.on) spdlog::info("tool light {}", m.on ? "on" : "off");
  sim.set_tool_light(m.on);
}

bool advance_to(Simulator& sim, double& clock_s, double now_s) {
  bool skipped = false;
  if (now_s - clock_s > kMaxLagS) {
    spdlog::warn("physics {:.3f} s behind the clock; skipping ahead", now_s - clock_s);
    clock_s = now_s - kPhysicsStepS;
    skipped = true;
  }
  while (clock_s + kPhysicsStepS <= now_s) {
    sim.step(kPhysicsStepS);
    clock_s += kPhysicsStepS;
  }
  return skipped;
}

shepherd_ground_truth_t ground_truth_message_of(const GroundTruth& gt, int64_t utime,
                                                int64_t frame_index) {
  shepherd_ground_truth_t m;
  m.utime = utime;
  m.frame_index = frame_index;
  m.escapes = gt.escapes;
  m.saves = gt.saves;
  m.sim_time_s = gt.time_s;
  for (const auto& s : gt.sheep) {
    shepherd_sheep_truth_t t;
    t.id = s.state.id;
    t.x_mm = static_cast<float>(s.state.centre_mm.x());
    t.y_mm = static_cast<float>(s.state.centre_mm.y());
    t.heading_rad = static_cast<float>(s.state.heading_rad());
    t.speed_mm_s = static_cast<float>(s.state.speed_mm_s());
    t.u = static_cast<float>(s.view.centre_px.x());
    t.v = static_cast<float>(s.view.centre_px.y());
    t.visible = s.view.visible;
    t.on_field = s.state.on_field;
    m.sheep.push_back(t);
  }
  m.num_sheep = static_cast<int32_t>(m.sheep.size());
  return m;
}

}  // namespace ephor::sim
