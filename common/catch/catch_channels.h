#pragma once
// The catching system's own LCM channels. Shared channels (CAMERA, ARM_GOAL,
// ARM_STATE, ...) are in common/lcm/channels.h.

namespace ephor::catching::channels {

inline constexpr const char* kBall = "CATCH_BALL";  // catch_ball_t, vision -> worldmodel
inline constexpr const char* kBoardPose =
    "CATCH_BOARD_POSE";                                 // catch_board_pose_t, vision -> worldmodel
inline constexpr const char* kWorld = "CATCH_WORLD";    // catch_world_t, worldmodel -> prim, vision
inline constexpr const char* kTruth = "CATCH_TRUTH";    // catch_truth_t, sim -> monitor, tests
inline constexpr const char* kSurvey = "CATCH_SURVEY";  // catch_survey_t, the arm's three touches
inline constexpr const char* kPegs = "CATCH_PEGS";  // catch_pegs_t, the board's pegs as measured

}  // namespace ephor::catching::channels
