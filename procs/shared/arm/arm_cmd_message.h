#pragma once
// The arm server's one conversion from the wire: an ARM_CMD message (as LCM
// decoded it) to the ArmCommand the validator and planner take. Shared by
// the process (main.cc) and its fuzz target, so both check the same thing.

#include "ephor/arm_cmd_t.hpp"
#include "procs/shared/arm/arm_command.h"

namespace ephor::arm {

// Copies every field; a trajectory's arrays as LCM's decoder kept them
// (num_points long). Nothing is checked here: CommandValidator does that.
ArmCommand command_from_message(const arm_cmd_t& m);

}  // namespace ephor::arm
