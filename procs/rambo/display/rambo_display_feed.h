#pragma once
// RamboDisplayFeed: ephor-rambo-display's LCM handlers and state builder
// without LCM or HTTP. Each message is checked and converted to
// RamboDisplayState's plain structs as the process takes it (a malformed one
// is dropped); state() is GET /api/state's system part, model() GET
// /api/model. Out of main.cc so that the fuzz target
// rambo_display_feed_fuzz.cc runs what the process runs, on any message.
// Nothing here ages: the page's state needs no clock.
//
// Not thread-safe: DisplayServer holds one lock around every call.

#include <nlohmann/json.hpp>

#include "common/rambo/rambo_cell.h"
#include "ephor/arm_state_t.hpp"
#include "ephor/rambo_features_t.hpp"
#include "ephor/rambo_indicator_t.hpp"
#include "ephor/rambo_plan_t.hpp"
#include "ephor/rambo_pose_t.hpp"
#include "ephor/rambo_truth_t.hpp"
#include "procs/rambo/display/rambo_display_state.h"

namespace ephor::rambo_display {

class RamboDisplayFeed {
 public:
  explicit RamboDisplayFeed(rambo::RamboCell cell) : state_(std::move(cell)) {}

  void on_features(const rambo_features_t& m);  // RAMBO_FEATURES (or --features-channel)
  void on_pose(const rambo_pose_t& m);
  void on_truth(const rambo_truth_t& m);
  void on_plan(const rambo_plan_t& m);
  void on_indicator(const rambo_indicator_t& m);
  void on_arm_state(const arm_state_t& m);

  nlohmann::json state() const { return state_.state(); }
  nlohmann::json model() const { return state_.model(); }

 private:
  RamboDisplayState state_;
};

}  // namespace ephor::rambo_display
