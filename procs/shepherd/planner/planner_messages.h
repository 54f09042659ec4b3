#pragma once
// ephor-planner's messages in and out, as its plan task converts them (out
// of main.cc, so that the fuzz target planner_messages_fuzz.cc runs what the
// process runs): an ARM_STATE as the arm the planner assumes, an OBJECTS
// entry as a sheep, a goal as the ARM_GOAL and a status as the
// PLANNER_STATUS it publishes.

#include <cstdint>
#include <optional>
#include <string>

#include "common/calibration/field_calibration.h"
#include "common/geometry/workcell.h"
#include "ephor/arm_goal_t.hpp"
#include "ephor/arm_state_t.hpp"
#include "ephor/shepherd_object_t.hpp"
#include "ephor/shepherd_planner_status_t.hpp"
#include "procs/shepherd/planner/herd_types.h"

namespace ephor::planner {

// The plane ARM_STATE says the tool rests on: none while moving or before
// the first completed motion.
std::optional<Plane> arm_plane(const arm_state_t& arm);

// `assumed` (speed and timings, --arm-speed-mm-s) with what ARM_STATE says:
// the tool tip's place (F, mm), lowered when it is below the middle of the
// work cell's two planes, and the joints (rad), known only when all are
// finite and put the tool tip within 20 mm of that place (a sender without
// joints leaves them zero). nullopt when the tip's place is not finite
// (counted by the caller; the assumed arm stays).
std::optional<ArmModel> arm_model_of(const arm_state_t& arm, const ArmModel& assumed,
                                     const geometry::Workcell& workcell);

// One OBJECTS entry as a sheep (F, mm and mm/s, unchecked: the planner
// counts and ignores non-finite sheep); nullopt for an unknown state
// (counted by the caller, ignored).
std::optional<Sheep> sheep_of(const shepherd_object_t& object);

// The goal as ARM_GOAL, in image coordinates as the paper's planner sent
// them: (u, v) px of the goal's point through the calibration of its plane,
// theta the image direction of a 10 mm step along the goal's orientation in
// F; the arm's own speed cap; its goal id offset by goal_id_offset (unique
// across restarts and planner switches); source_utime the capture time of
// the OBJECTS it was planned from. utime is the caller's to set.
arm_goal_t goal_message_of(const Goal& goal, const calibration::FieldCalibration& calibration,
                           int64_t goal_id_offset, int64_t source_utime);

// The planner's own id (Planner::on_motion_done) of the ARM_GOAL id a
// MOTION_DONE names: goal_message_of()'s offset taken off again; -1 (no
// goal's: planners count their goals from 1) when that does not fit in
// int64_t.
int64_t planner_goal_id(int64_t arm_goal_id, int64_t goal_id_offset);

// The planner's status as PLANNER_STATUS: the intercept in the image
// (object plane, px), the goal id offset as the goals', planning_us the
// job's time (us). The header is the bus's to set.
shepherd_planner_status_t status_message_of(const PlannerStatus& status, const std::string& kind,
                                            const calibration::FieldCalibration& calibration,
                                            int64_t goal_id_offset, int64_t source_utime,
                                            float planning_us);

}  // namespace ephor::planner
