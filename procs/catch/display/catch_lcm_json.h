#pragma once
// JSON forms of the catching system's LCM messages, for its page's debug
// dump (GET /api/debug). Part of ephor-catch-display.

#include <nlohmann/json.hpp>

#include "common/display/lcm_json.h"
#include "ephor/catch_ball_t.hpp"
#include "ephor/catch_board_pose_t.hpp"
#include "ephor/catch_survey_t.hpp"
#include "ephor/catch_truth_t.hpp"
#include "ephor/catch_world_t.hpp"

namespace ephor {

void to_json(nlohmann::json& j, const catch_ball_t& m);
void to_json(nlohmann::json& j, const catch_board_pose_t& m);
void to_json(nlohmann::json& j, const catch_survey_t& m);
void to_json(nlohmann::json& j, const catch_world_t& m);
void to_json(nlohmann::json& j, const catch_truth_t& m);

}  // namespace ephor
