#pragma once
// CatchDisplayFeed: ephor-catch-display's LCM handlers and state builder
// without LCM or HTTP. Each message is converted to CatchDisplayState's
// plain structs as the process takes it; state() is GET /api/state's system
// part. Out of main.cc so that the fuzz target catch_display_feed_fuzz.cc
// runs what the process runs, on any message.
//
// Not thread-safe: DisplayServer holds one lock around every call.

#include <cstdint>

#include <nlohmann/json.hpp>

#include "ephor/arm_state_t.hpp"
#include "ephor/camera_frame_t.hpp"
#include "ephor/catch_ball_t.hpp"
#include "ephor/catch_board_pose_t.hpp"
#include "ephor/catch_survey_t.hpp"
#include "ephor/catch_truth_t.hpp"
#include "ephor/catch_world_t.hpp"
#include "procs/catch/display/catch_display_state.h"

namespace ephor::catch_display {

class CatchDisplayFeed {
 public:
  CatchDisplayFeed(catching::BoardSpec board, catching::CameraIntrinsics camera)
      : state_(std::move(board), std::move(camera)) {}

  // `now_us`: this host's wall clock when the message arrived (us).
  void on_frame(const camera_frame_t& m, int64_t now_us);  // CAMERA (the frame hook)
  void on_board_pose(const catch_board_pose_t& m, int64_t now_us);
  void on_survey(const catch_survey_t& m, int64_t now_us);
  void on_ball(const catch_ball_t& m, int64_t now_us);
  void on_world(const catch_world_t& m, int64_t now_us);
  void on_truth(const catch_truth_t& m, int64_t now_us);
  void on_arm_state(const arm_state_t& m, int64_t now_us);

  // GET /api/state's system part at wall clock `now_us` (us).
  nlohmann::json state(int64_t now_us) const { return state_.to_json(now_us); }

  const CatchDisplayState& display_state() const { return state_; }

 private:
  CatchDisplayState state_;
};

}  // namespace ephor::catch_display
