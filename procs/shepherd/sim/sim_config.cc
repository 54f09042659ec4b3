#include "procs/shepherd/sim/sim_config.h"

#include <cmath>
#include <stdexcept>

#include "common/config/text_proto.h"
#include "procs/shepherd/sim/sim_config.pb.h"

namespace ephor::sim {

void apply_config_file(const std::string& path, SimulatorConfig& config, double& fps) {
  SimConfig file;
  TextProto text(path, &file);
  auto& w = config.world;
  auto& c = config.camera;
  if (file.has_sheep()) w.sheep = file.sheep();
  if (file.has_seed()) w.seed = file.seed();
  if (file.has_speed_mm_s()) w.speed_mm_s = file.speed_mm_s();
  if (file.has_speed_spread()) w.speed_spread = file.speed_spread();
  if (file.has_wander_rad_s()) w.wander_rad_s = file.wander_rad_s();
  if (file.has_wander_time_s()) w.wander_time_s = file.wander_time_s();
  if (file.has_reentry_s()) w.reentry_s = file.reentry_s();
  if (file.has_field_length_mm()) w.workcell.field_length_mm = file.field_length_mm();
  if (file.has_field_width_mm()) w.workcell.field_width_mm = file.field_width_mm();
  if (file.has_fps()) {
    if (!std::isfinite(file.fps()) || file.fps() <= 0.0 || file.fps() > 1000.0)
      text.fail("fps", "must be in (0, 1000]");
    fps = file.fps();
  }
  if (file.has_noise_sigma()) c.noise_sigma = file.noise_sigma();
  if (file.has_gain_gradient()) c.gain_gradient = file.gain_gradient();
  if (file.has_vignette()) c.vignette = file.vignette();
  if (file.has_field_level()) c.field_level = file.field_level();
  if (file.has_body_level()) c.body_level = file.body_level();
  if (file.has_arm_level()) c.arm_level = file.arm_level();
  if (file.has_mark_level()) c.mark_level = file.mark_level();
  if (file.has_surround_level()) c.surround_level = file.surround_level();
  // Semantic checks, reported against the file.
  try {
    validate(w);
    validate(c);
  } catch (const std::invalid_argument& e) {
    throw ConfigError(path + ": " + e.what());
  }
}

}  // namespace ephor::sim
