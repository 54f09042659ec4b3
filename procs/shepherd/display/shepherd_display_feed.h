#pragma once
// ShepherdDisplayFeed: ephor-display's LCM handlers and state builder
// without LCM or HTTP. Each message the page hears is converted as the
// process takes it into DisplayState's plain structs, and the page's
// controls follow what the other processes were last commanded. Out of
// main.cc so that the fuzz target shepherd_display_feed_fuzz.cc runs what the
// process runs. DisplayServer holds its lock around every call.

#include <cstdint>
#include <memory>

#include <nlohmann/json.hpp>

#include "ephor/arm_cmd_t.hpp"
#include "ephor/arm_state_t.hpp"
#include "ephor/camera_frame_t.hpp"
#include "ephor/shepherd_blobs_t.hpp"
#include "ephor/shepherd_ground_truth_t.hpp"
#include "ephor/shepherd_objects_t.hpp"
#include "ephor/shepherd_planner_cmd_t.hpp"
#include "ephor/shepherd_planner_status_t.hpp"
#include "ephor/shepherd_sim_cmd_t.hpp"
#include "ephor/shepherd_vision_cmd_t.hpp"
#include "procs/shepherd/display/command_validator.h"
#include "procs/shepherd/display/display_state.h"

namespace ephor::display {

class ShepherdDisplayFeed {
 public:
  // `sim_seed`: the simulator's seed, sent back unchanged in the full-state
  // SIM_CMD until a SIM_CMD names another.
  ShepherdDisplayFeed(const OverlayGeometry& geometry, const DisplayOptions& options, int sim_seed);

  // `now_us`: this host's wall clock when the message arrived.
  void on_frame(const camera_frame_t& m, int64_t now_us);
  void on_blobs(const shepherd_blobs_t& m, int64_t now_us);
  void on_vision_cmd(const shepherd_vision_cmd_t& m);
  void on_objects(const shepherd_objects_t& m, int64_t now_us);
  void on_planner_status(const shepherd_planner_status_t& m, int64_t now_us);
  void on_planner_cmd(const shepherd_planner_cmd_t& m);
  void on_arm_state(const arm_state_t& m, int64_t now_us);
  void on_truth(const shepherd_ground_truth_t& m, int64_t now_us);
  void on_sim_cmd(const shepherd_sim_cmd_t& m);
  void on_arm_cmd(const arm_cmd_t& m);

  // The page's state (GET /api/state, before DisplayServer adds its part).
  nlohmann::json state(int64_t now_us) const { return state_.to_json(controls_, now_us); }

  // The controls as last commanded (the page sends them whole), and the
  // newest frame's size (which bounds the calibration box).
  const Controls& controls() const { return controls_; }
  void set_controls(const Controls& c) { controls_ = c; }
  int frame_width() const { return frame_width_; }
  int frame_height() const { return frame_height_; }

 private:
  DisplayState state_;
  Controls controls_;
  // Whether each control came from its process (a command or an output seen),
  // so the page does not send a default over what the process is doing.
  bool vision_known_ = false;
  bool sim_known_ = false;
  bool planner_known_ = false;
  int frame_width_ = 512;  // px
  int frame_height_ = 482;
};

}  // namespace ephor::display
