#include "common/display/lcm_json.h"

namespace ephor {

EPHOR_TO_JSON(header_t, utime, sender, seq)
EPHOR_TO_JSON(arm_goal_t, utime, header, goal_id, plane, u, v, theta_rad, max_speed_mm_s,
              source_frame_utime, target_object)
EPHOR_TO_JSON(arm_cmd_t, utime, header, seq, goal_id, plane, u, v, theta_rad, max_speed_mm_s,
              source_frame_utime)
EPHOR_TO_JSON(arm_ack_t, utime, header, seq, goal_id, status, reason, planned_duration_s)
EPHOR_TO_JSON(motion_done_t, utime, header, goal_id, seq, status, reason, attempts)
EPHOR_TO_JSON(arm_state_t, utime, header, q, qd, x_mm, y_mm, z_mm, u, v, theta_rad, plane, moving,
              executing_seq, last_done_seq, speed_mm_s)
EPHOR_TO_JSON(estop_t, utime, header, stop, reason)
EPHOR_TO_JSON(task_status_t, utime, process, task, pid, tid, cpu, assigned_cpu, policy, priority,
              periodic, period_us, deadline_us, exec_p50_us, exec_p99_us, exec_max_us,
              jitter_p50_us, jitter_p99_us, jitter_max_us, jobs, deadline_misses, utilisation,
              rt_granted, alive)
EPHOR_TO_JSON(sched_status_t, utime, header, host, rt, num_cpus, cpu_utilisation, cpu_bound,
              num_tasks, tasks, num_events, events)

void to_json(nlohmann::json& j, const camera_frame_t& m) {
  j = {{"utime", m.utime},
       {"header", m.header},
       {"frame_index", m.frame_index},
       {"width", m.width},
       {"height", m.height},
       {"size", m.size},
       {"data", "(" + std::to_string(m.size) + " bytes, not dumped)"}};
}

camera_frame_t frame_fields(const camera_frame_t& m) {
  camera_frame_t fields;
  fields.utime = m.utime;
  fields.header = m.header;
  fields.frame_index = m.frame_index;
  fields.width = m.width;
  fields.height = m.height;
  fields.size = m.size;
  return fields;
}

}  // namespace ephor
