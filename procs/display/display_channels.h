#pragma once
// Channels introduced by the display (to move into common/lcm/channels.h).

namespace ephor::display::channels {

inline constexpr const char* kPlannerCmd = "PLANNER_CMD";  // planner_cmd_t, display -> planner
inline constexpr const char* kDisplayBox =
    "DISPLAY_BOX";  // display_box_t, display -> calibration tools

}  // namespace ephor::display::channels
