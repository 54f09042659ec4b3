#include "procs/sphere/guidance/guidance_messages.h"

namespace ephor::sphere {

EstimateInput estimate_input_of(const sphere_estimate_t& m) {
  EstimateInput e;
  e.window = m.window;
  e.window_end_s = m.window_end_s;
  e.ok = m.ok;
  e.t_s = m.t_s;
  e.position_m = Eigen::Vector3d(m.position_m[0], m.position_m[1], m.position_m[2]);
  e.velocity_m_s = Eigen::Vector3d(m.velocity_m_s[0], m.velocity_m_s[1], m.velocity_m_s[2]);
  return e;
}

sphere_guidance_t guidance_message_of(const GuidanceOutput& out, const SphereGuidance& guidance,
                                      const GuidanceConfig& config) {
  sphere_guidance_t g{};
  g.apply_t_s = out.apply_t_s;
  g.t_s = out.state.t_s;
  for (int i = 0; i < 3; ++i) {
    g.chaser_velocity_m_s[i] = out.command.chaser_velocity_m_s[i];
    g.position_m[i] = out.state.position_m[i];
    g.velocity_m_s[i] = out.state.velocity_m_s[i];
    g.position_sigma_m[i] = out.state.position_sigma_m[i];
    g.velocity_sigma_m_s[i] = out.state.velocity_sigma_m_s[i];
  }
  g.range_to_capture_m = out.state.position_m.z() - config.approach.capture_distance_m;
  g.phase = static_cast<int8_t>(out.command.phase);
  g.estimates_used = guidance.estimates_used();
  g.estimates_rejected = guidance.estimates_rejected();
  g.estimates_downweighted = guidance.estimates_downweighted();
  g.no_estimates = guidance.no_estimates();
  return g;
}

}  // namespace ephor::sphere
