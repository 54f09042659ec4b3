#pragma once
// LCM channel names of the application (see lcmtypes/ for each type).
// Runtime/scheduler channels are in common/runtime/channels.h.

namespace ephor::channels {

inline constexpr const char* kCamera = "CAMERA";  // camera_frame_t, sim or camera -> vision
inline constexpr const char* kGroundTruth =
    "GROUND_TRUTH";  // shepherd_ground_truth_t, sim -> tests/display only
inline constexpr const char* kSimCmd = "SIM_CMD";  // shepherd_sim_cmd_t, display/tests -> sim
inline constexpr const char* kSimToolLight =
    "SIM_TOOL_LIGHT";                                    // shepherd_tool_light_t, calibrate -> sim
inline constexpr const char* kBlobs = "BLOBS";           // shepherd_blobs_t, vision -> worldmodel
inline constexpr const char* kVisionCmd = "VISION_CMD";  // shepherd_vision_cmd_t, display -> vision
inline constexpr const char* kObjects = "OBJECTS";  // shepherd_objects_t, worldmodel -> planner
inline constexpr const char* kPlannerStatus =
    "PLANNER_STATUS";  // shepherd_planner_status_t, planner -> display
inline constexpr const char* kArmGoal = "ARM_GOAL";        // arm_goal_t, planner -> comm
inline constexpr const char* kMotionDone = "MOTION_DONE";  // motion_done_t, comm -> planner
inline constexpr const char* kArmCmd = "ARM_CMD";          // arm_cmd_t, comm -> arm
inline constexpr const char* kArmAck = "ARM_ACK";          // arm_ack_t, arm -> comm
inline constexpr const char* kArmState = "ARM_STATE";  // arm_state_t, arm -> everyone, >= 100 Hz
inline constexpr const char* kArmTrajectory =
    "ARM_TRAJECTORY";                                  // joint_trajectory_t, arm -> servo (sim)
inline constexpr const char* kArmServo = "ARM_SERVO";  // joint_state_t, servo (sim) -> arm
inline constexpr const char* kEstop = "ESTOP";         // estop_t, anyone -> arm (latched stop)
inline constexpr const char* kPlannerCmd =
    "PLANNER_CMD";  // shepherd_planner_cmd_t, display -> planner
inline constexpr const char* kDisplayBox =
    "DISPLAY_BOX";  // shepherd_display_box_t, display -> calibration tools

}  // namespace ephor::channels
