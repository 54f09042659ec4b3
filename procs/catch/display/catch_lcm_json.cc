#include "procs/catch/display/catch_lcm_json.h"

namespace ephor {

EPHOR_TO_JSON(catch_ball_t, utime, header, frame_index, found, u, v, u_blob, v_blob, area_px,
              window, exec_ms)
EPHOR_TO_JSON(catch_board_pose_t, utime, header, valid, reason, r, t_mm, circles_px,
              reprojection_rms_px, ippe_error_ratio)
EPHOR_TO_JSON(catch_survey_t, utime, header, board_mm, world_mm)
EPHOR_TO_JSON(catch_world_t, utime, header, frame_index, status, ball_id, reason, position_b_mm,
              velocity_b_mm_s, measured_b_mm, position_w_mm, has_prediction, exit_x_b_mm,
              exit_sigma_mm, exit_utime, exit_sigma_s, catch_point_w_mm, catch_utime, latency_ms)
EPHOR_TO_JSON(catch_truth_t, utime, header, frame_index, ball, phase, ball_b_mm,
              ball_velocity_b_mm_s, ball_w_mm, ball_px, exit_x_b_mm, exit_utime, cup_w_mm,
              incline_deg, board_to_camera_r, board_to_camera_t_mm, balls_done, caught,
              oracle_reachable, last_ball, last_caught, last_oracle_reachable, last_reason)

}  // namespace ephor
