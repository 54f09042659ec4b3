#pragma once
// JSON forms of the LCM messages the display hears, for the debug dump
// (GET /api/debug: the newest message of every channel). Part of the
// ephor-display executable, not of the pure library: it knows the LCM types.
// Camera frames are summarised (size, index), not dumped pixel by pixel.

#include <nlohmann/json.hpp>

#include "ephor/arm_ack_t.hpp"
#include "ephor/arm_cmd_t.hpp"
#include "ephor/arm_goal_t.hpp"
#include "ephor/arm_state_t.hpp"
#include "ephor/camera_frame_t.hpp"
#include "ephor/motion_done_t.hpp"
#include "ephor/sched_status_t.hpp"
#include "ephor/shepherd_blobs_t.hpp"
#include "ephor/shepherd_display_box_t.hpp"
#include "ephor/shepherd_ground_truth_t.hpp"
#include "ephor/shepherd_objects_t.hpp"
#include "ephor/shepherd_planner_cmd_t.hpp"
#include "ephor/shepherd_planner_status_t.hpp"
#include "ephor/shepherd_sim_cmd_t.hpp"
#include "ephor/shepherd_vision_cmd_t.hpp"

namespace ephor {

void to_json(nlohmann::json& j, const header_t& m);
void to_json(nlohmann::json& j, const camera_frame_t& m);
void to_json(nlohmann::json& j, const shepherd_blob_t& m);
void to_json(nlohmann::json& j, const shepherd_blobs_t& m);
void to_json(nlohmann::json& j, const shepherd_vision_cmd_t& m);
void to_json(nlohmann::json& j, const shepherd_object_t& m);
void to_json(nlohmann::json& j, const shepherd_objects_t& m);
void to_json(nlohmann::json& j, const shepherd_planner_status_t& m);
void to_json(nlohmann::json& j, const shepherd_planner_cmd_t& m);
void to_json(nlohmann::json& j, const arm_goal_t& m);
void to_json(nlohmann::json& j, const arm_cmd_t& m);
void to_json(nlohmann::json& j, const arm_ack_t& m);
void to_json(nlohmann::json& j, const motion_done_t& m);
void to_json(nlohmann::json& j, const arm_state_t& m);
void to_json(nlohmann::json& j, const shepherd_sheep_truth_t& m);
void to_json(nlohmann::json& j, const shepherd_ground_truth_t& m);
void to_json(nlohmann::json& j, const shepherd_sim_cmd_t& m);
void to_json(nlohmann::json& j, const task_status_t& m);
void to_json(nlohmann::json& j, const sched_status_t& m);
void to_json(nlohmann::json& j, const shepherd_display_box_t& m);

}  // namespace ephor
