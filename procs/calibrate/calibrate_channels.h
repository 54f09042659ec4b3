#pragma once
// LCM channel of the calibration light (lcmtypes/tool_light_t.lcm). Kept here,
// beside its only publisher, until common/lcm/channels.h takes it.

namespace ephor::channels {

inline constexpr const char* kSimToolLight = "SIM_TOOL_LIGHT";  // tool_light_t, calibrate -> sim

}  // namespace ephor::channels
