#include "procs/sphere/display/sphere_lcm_json.h"

namespace ephor {

EPHOR_TO_JSON(sphere_scan_line_t, utime, header, line, window, window_s, last_in_window,
              half_extent_deg, num_pulses, t_s, azimuth_rad, elevation_rad, range_m)
EPHOR_TO_JSON(sphere_estimate_t, utime, header, window, window_begin_s, window_end_s, ok, reason,
              t_s, position_m, velocity_m_s, points, lines, lines_received, lines_missing, cpu_us,
              algorithm, variant)
EPHOR_TO_JSON(sphere_guidance_t, utime, header, apply_t_s, chaser_velocity_m_s, t_s, position_m,
              velocity_m_s, position_sigma_m, velocity_sigma_m_s, range_to_capture_m, phase,
              estimates_used, estimates_downweighted, estimates_rejected, no_estimates)
EPHOR_TO_JSON(sphere_truth_t, utime, header, t_s, approach, phase, position_m, velocity_m_s,
              chaser_velocity_m_s, target_velocity_m_s, half_extent_deg, capture_t_s,
              capture_speed_m_s, capture_offset_m, verdict)

}  // namespace ephor
