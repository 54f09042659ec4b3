#pragma once
// JSON forms of the sphere system's LCM messages, for its page's debug dump
// (GET /api/debug). Part of ephor-sphere-display.

#include <nlohmann/json.hpp>

#include "common/display/lcm_json.h"
#include "ephor/sphere_estimate_t.hpp"
#include "ephor/sphere_guidance_t.hpp"
#include "ephor/sphere_scan_line_t.hpp"
#include "ephor/sphere_truth_t.hpp"

namespace ephor {

void to_json(nlohmann::json& j, const sphere_scan_line_t& m);
void to_json(nlohmann::json& j, const sphere_estimate_t& m);
void to_json(nlohmann::json& j, const sphere_guidance_t& m);
void to_json(nlohmann::json& j, const sphere_truth_t& m);

}  // namespace ephor
