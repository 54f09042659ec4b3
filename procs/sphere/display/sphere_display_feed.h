#pragma once
// SphereDisplayFeed: ephor-sphere-display's LCM handlers and state builders
// without LCM or HTTP. Each message is converted to SphereDisplayState's
// plain structs as the process takes it; state() is GET /api/state's system
// part, scan() GET /api/scan. Out of main.cc so that the fuzz target
// sphere_display_feed_fuzz.cc runs what the process runs, on any message.
//
// Not thread-safe: DisplayServer holds one lock around every call.

#include <cstdint>

#include <nlohmann/json.hpp>

#include "ephor/sphere_estimate_t.hpp"
#include "ephor/sphere_guidance_t.hpp"
#include "ephor/sphere_scan_line_t.hpp"
#include "ephor/sphere_truth_t.hpp"
#include "procs/sphere/display/sphere_display_state.h"

namespace ephor::sphere_display {

class SphereDisplayFeed {
 public:
  explicit SphereDisplayFeed(SphereDisplayOptions options = {}) : state_(options) {}

  // `now_us`: this host's wall clock when the message arrived (us).
  void on_scan_line(const sphere_scan_line_t& m, int64_t now_us);
  void on_estimate(const sphere_estimate_t& m, int64_t now_us);
  void on_guidance(const sphere_guidance_t& m, int64_t now_us);
  void on_truth(const sphere_truth_t& m, int64_t now_us);

  // GET /api/state's system part at wall clock `now_us` (us).
  nlohmann::json state(int64_t now_us) const { return state_.to_json(now_us); }
  // GET /api/scan: the newest complete raster's points.
  nlohmann::json scan() const { return state_.scan_json(); }

 private:
  SphereDisplayState state_;
};

}  // namespace ephor::sphere_display
