#include "procs/shepherd/display/shepherd_lcm_json.h"

namespace ephor {

EPHOR_TO_JSON(shepherd_blob_t, u, v, area, u_min, v_min, u_max, v_max)
EPHOR_TO_JSON(shepherd_blobs_t, utime, header, frame_index, mode, scan, threshold, processing_us,
              num_blobs, blobs)
EPHOR_TO_JSON(shepherd_vision_cmd_t, utime, header, paused, mode, scan, threshold)
EPHOR_TO_JSON(shepherd_object_t, id, state, u, v, x_mm, y_mm, vu_px_s, vv_px_s, vx_mm_s, vy_mm_s,
              since_seen_s, area)
EPHOR_TO_JSON(shepherd_objects_t, utime, header, frame_index, num_objects, objects)
EPHOR_TO_JSON(shepherd_planner_status_t, utime, header, planner, phase, target_object, intercept_u,
              intercept_v, intercept_time_s, num_candidates, planning_us, goal_id)
EPHOR_TO_JSON(shepherd_planner_cmd_t, utime, header, planner)
EPHOR_TO_JSON(shepherd_sheep_truth_t, id, x_mm, y_mm, heading_rad, speed_mm_s, u, v, visible,
              on_field)
EPHOR_TO_JSON(shepherd_ground_truth_t, utime, header, frame_index, num_sheep, sheep, escapes, saves,
              sim_time_s)
EPHOR_TO_JSON(shepherd_sim_cmd_t, utime, header, sheep, reset, seed)
EPHOR_TO_JSON(shepherd_display_box_t, utime, header, visible, u, v, half_size_px)

}  // namespace ephor
