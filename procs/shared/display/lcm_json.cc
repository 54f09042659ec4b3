#include "procs/shared/display/lcm_json.h"

// Member-wise to_json, as nlohmann's NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE but
// without from_json (not needed, and C arrays such as arm_state_t.q need none).
#define EPHOR_TO_JSON(Type, ...)                                               \
  void to_json(nlohmann::json& nlohmann_json_j, const Type& nlohmann_json_t) { \
    NLOHMANN_JSON_EXPAND(NLOHMANN_JSON_PASTE(NLOHMANN_JSON_TO, __VA_ARGS__))   \
  }

namespace ephor {

EPHOR_TO_JSON(header_t, utime, sender, seq)
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
EPHOR_TO_JSON(arm_goal_t, utime, header, goal_id, plane, u, v, theta_rad, max_speed_mm_s,
              source_frame_utime, target_object)
EPHOR_TO_JSON(arm_cmd_t, utime, header, seq, goal_id, plane, u, v, theta_rad, max_speed_mm_s,
              source_frame_utime)
EPHOR_TO_JSON(arm_ack_t, utime, header, seq, goal_id, status, reason, planned_duration_s)
EPHOR_TO_JSON(motion_done_t, utime, header, goal_id, seq, status, reason, attempts)
EPHOR_TO_JSON(arm_state_t, utime, header, q, qd, x_mm, y_mm, z_mm, u, v, theta_rad, plane, moving,
              executing_seq, last_done_seq, speed_mm_s)
EPHOR_TO_JSON(shepherd_sheep_truth_t, id, x_mm, y_mm, heading_rad, speed_mm_s, u, v, visible,
              on_field)
EPHOR_TO_JSON(shepherd_ground_truth_t, utime, header, frame_index, num_sheep, sheep, escapes, saves,
              sim_time_s)
EPHOR_TO_JSON(shepherd_sim_cmd_t, utime, header, sheep, reset, seed)
EPHOR_TO_JSON(task_status_t, utime, process, task, pid, tid, cpu, assigned_cpu, policy, priority,
              periodic, period_us, deadline_us, exec_p50_us, exec_p99_us, exec_max_us,
              jitter_p50_us, jitter_p99_us, jitter_max_us, jobs, deadline_misses, utilisation,
              rt_granted, alive)
EPHOR_TO_JSON(sched_status_t, utime, header, host, rt, num_cpus, cpu_utilisation, cpu_bound,
              num_tasks, tasks, num_events, events)
EPHOR_TO_JSON(shepherd_display_box_t, utime, header, visible, u, v, half_size_px)

void to_json(nlohmann::json& j, const camera_frame_t& m) {
  j = {{"utime", m.utime},
       {"header", m.header},
       {"frame_index", m.frame_index},
       {"width", m.width},
       {"height", m.height},
       {"size", m.size},
       {"data", "(" + std::to_string(m.size) + " bytes, not dumped)"}};
}

}  // namespace ephor
