#include "procs/stripe/display/stripe_display_feed.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "common/display/json_format.h"

namespace ephor::stripe_display {
namespace {

using display::rounded;

const char* state_name(int s) {
  switch (s) {
    case stripe_scan_t::STATE_WAITING:
      return "waiting";
    case stripe_scan_t::STATE_RUNNING:
      return "running";
    case stripe_scan_t::STATE_CAPTURED:
      return "captured";
    case stripe_scan_t::STATE_DONE:
      return "done";
    case stripe_scan_t::STATE_FAILED:
      return "failed";
  }
  return "unknown";
}

}  // namespace

void StripeDisplayFeed::on_scan(const stripe_scan_t& m) {
  if (!have_scan_ || m.scan_id != scan_.scan_id) {  // a new scan: a new cloud
    xyz_.clear();
    stripes_ = 0;
    have_cloud_ = false;
  }
  have_scan_ = true;
  scan_ = m;
}

void StripeDisplayFeed::on_points(const stripe_points_t& m) {
  if (!have_scan_ || m.scan_id != scan_.scan_id || m.scan_id == 0) return;
  const auto n = static_cast<size_t>(std::max(0, m.num_points));
  if (m.x_mm.size() != n || m.y_mm.size() != n || m.z_mm.size() != n) return;
  for (size_t i = 0; i < n; ++i) {
    if (!std::isfinite(m.x_mm[i]) || !std::isfinite(m.y_mm[i]) || !std::isfinite(m.z_mm[i]))
      continue;
    xyz_.push_back(m.x_mm[i]);
    xyz_.push_back(m.y_mm[i]);
    xyz_.push_back(m.z_mm[i]);
  }
  ++stripes_;
}

void StripeDisplayFeed::on_cloud(const stripe_cloud_t& m) {
  if (!have_scan_ || m.scan_id != scan_.scan_id) return;
  have_cloud_ = true;
  cloud_ = m;
}

nlohmann::json StripeDisplayFeed::state() const {
  nlohmann::json j;
  if (have_scan_) {
    const stripe_scan_t& m = scan_;
    j["scan"] = {{"scan_id", m.scan_id},
                 {"state", state_name(m.state)},
                 {"reason", m.reason},
                 {"region_mm",
                  {rounded(m.region_mm[0], 1), rounded(m.region_mm[1], 1),
                   rounded(m.region_mm[2], 1), rounded(m.region_mm[3], 1)}},
                 {"step_mm", rounded(m.step_mm, 2)},
                 {"height_mm", rounded(m.height_mm, 1)},
                 {"stripes_planned", m.stripes_planned},
                 {"stripes_captured", m.stripes_captured},
                 {"stripes_skipped", m.stripes_skipped},
                 {"elapsed_s", rounded(m.elapsed_s, 2)},
                 {"stripes_per_s", rounded(m.stripes_per_s, 2)}};
  } else {
    j["scan"] = nullptr;
  }
  j["cloud"] = {{"points", xyz_.size() / 3},
                {"stripes", stripes_},
                {"complete", have_cloud_},
                {"path", have_cloud_ ? cloud_.path : ""}};
  return j;
}

nlohmann::json StripeDisplayFeed::cloud() const {
  // Points to 0.1 mm: a third of the text, finer than the view shows.
  nlohmann::json xyz = nlohmann::json::array();
  for (float v : xyz_) xyz.push_back(rounded(v, 1));
  return nlohmann::json{{"scan_id", have_scan_ ? scan_.scan_id : 0},
                        {"points", xyz_.size() / 3},
                        {"xyz", std::move(xyz)}};
}

}  // namespace ephor::stripe_display
