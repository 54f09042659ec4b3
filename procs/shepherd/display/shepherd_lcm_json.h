#pragma once
// JSON forms of the shepherding system's own LCM messages, for its page's
// debug dump (the shared ones are in lcm_json.h). Part of ephor-display.

#include <nlohmann/json.hpp>

#include "common/display/lcm_json.h"
#include "ephor/shepherd_blobs_t.hpp"
#include "ephor/shepherd_display_box_t.hpp"
#include "ephor/shepherd_ground_truth_t.hpp"
#include "ephor/shepherd_objects_t.hpp"
#include "ephor/shepherd_planner_cmd_t.hpp"
#include "ephor/shepherd_planner_status_t.hpp"
#include "ephor/shepherd_sim_cmd_t.hpp"
#include "ephor/shepherd_vision_cmd_t.hpp"

namespace ephor {

void to_json(nlohmann::json& j, const shepherd_blob_t& m);
void to_json(nlohmann::json& j, const shepherd_blobs_t& m);
void to_json(nlohmann::json& j, const shepherd_vision_cmd_t& m);
void to_json(nlohmann::json& j, const shepherd_object_t& m);
void to_json(nlohmann::json& j, const shepherd_objects_t& m);
void to_json(nlohmann::json& j, const shepherd_planner_status_t& m);
void to_json(nlohmann::json& j, const shepherd_planner_cmd_t& m);
void to_json(nlohmann::json& j, const shepherd_sheep_truth_t& m);
void to_json(nlohmann::json& j, const shepherd_ground_truth_t& m);
void to_json(nlohmann::json& j, const shepherd_sim_cmd_t& m);
void to_json(nlohmann::json& j, const shepherd_display_box_t& m);

}  // namespace ephor
