#pragma once
// JSON forms of the shared LCM messages a display hears, for the debug dump
// (GET /api/debug: the newest message of every channel; NewestMessages).
// Part of the LCM-aware display server, not of the pure library. A system's
// own messages get theirs in the system's display folder, written with
// EPHOR_TO_JSON below. Camera frames are summarised (size, index), not
// dumped pixel by pixel.

#include <nlohmann/json.hpp>

#include "ephor/arm_ack_t.hpp"
#include "ephor/arm_cmd_t.hpp"
#include "ephor/arm_goal_t.hpp"
#include "ephor/arm_state_t.hpp"
#include "ephor/camera_frame_t.hpp"
#include "ephor/estop_t.hpp"
#include "ephor/motion_done_t.hpp"
#include "ephor/sched_status_t.hpp"

// Member-wise to_json, as nlohmann's NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE but
// without from_json (not needed, and C arrays such as arm_state_t.q need none).
#define EPHOR_TO_JSON(Type, ...)                                               \
  void to_json(nlohmann::json& nlohmann_json_j, const Type& nlohmann_json_t) { \
    NLOHMANN_JSON_EXPAND(NLOHMANN_JSON_PASTE(NLOHMANN_JSON_TO, __VA_ARGS__))   \
  }

namespace ephor {

void to_json(nlohmann::json& j, const header_t& m);
void to_json(nlohmann::json& j, const camera_frame_t& m);
void to_json(nlohmann::json& j, const arm_goal_t& m);
void to_json(nlohmann::json& j, const arm_cmd_t& m);
void to_json(nlohmann::json& j, const arm_ack_t& m);
void to_json(nlohmann::json& j, const motion_done_t& m);
void to_json(nlohmann::json& j, const arm_state_t& m);
void to_json(nlohmann::json& j, const estop_t& m);
void to_json(nlohmann::json& j, const task_status_t& m);
void to_json(nlohmann::json& j, const sched_status_t& m);

// A camera frame's fields without its pixels: what the debug dump keeps of
// the newest frame (no second copy of the image).
camera_frame_t frame_fields(const camera_frame_t& m);

}  // namespace ephor
