#pragma once
// StripeDisplayFeed: ephor-stripe-display's LCM handlers and state builders
// without LCM or HTTP, with the page's state: the newest scan, the current
// scan's points as they arrive stripe by stripe, and the finished cloud's
// message. state() is GET /api/state's system part, cloud() GET /api/cloud.
// Out of main.cc so that the fuzz target stripe_display_feed_fuzz.cc runs
// what the process runs, on any message.
//
// Frames and units: points in mm, table frame (as STRIPE_POINTS carries
// them); times in s.
//
// Not thread-safe: DisplayServer holds one lock around every call.

#include <vector>

#include <nlohmann/json.hpp>

#include "ephor/stripe_cloud_t.hpp"
#include "ephor/stripe_points_t.hpp"
#include "ephor/stripe_scan_t.hpp"

namespace ephor::stripe_display {

class StripeDisplayFeed {
 public:
  // A scan of a new id starts a new cloud.
  void on_scan(const stripe_scan_t& m);
  // A stripe's points, of the current scan only; points not finite are left out.
  void on_points(const stripe_points_t& m);
  // The finished cloud, of the current scan only.
  void on_cloud(const stripe_cloud_t& m);

  // GET /api/state's system part: {scan: {scan_id, state, reason, ...} or
  // null, cloud: {points, stripes, complete, path}}. Numbers rounded (mm to
  // 0.1, s to 0.01); one that is not finite is written as 0.
  nlohmann::json state() const;
  // GET /api/cloud: {scan_id, points, xyz: [x, y, z, ...]} (mm to 0.1, table frame).
  nlohmann::json cloud() const;

 private:
  bool have_scan_ = false;
  stripe_scan_t scan_{};
  std::vector<float> xyz_;  // the current scan's points, mm, table frame
  int stripes_ = 0;
  bool have_cloud_ = false;
  stripe_cloud_t cloud_{};
};

}  // namespace ephor::stripe_display
