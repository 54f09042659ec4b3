#include "procs/sphere/display/sphere_display_feed.h"

namespace ephor::sphere_display {
namespace {

Vec3 vec(const double (&v)[3]) { return {v[0], v[1], v[2]}; }

}  // namespace

void SphereDisplayFeed::on_scan_line(const sphere_scan_line_t& m, int64_t now_us) {
  ScanLineView l;
  l.line = m.line;
  l.window = m.window;
  l.last_in_window = m.last_in_window;
  l.half_extent_deg = m.half_extent_deg;
  l.azimuth_rad = m.azimuth_rad;
  l.elevation_rad = m.elevation_rad;
  l.range_m = m.range_m;
  state_.on_scan_line(l, now_us);
}

void SphereDisplayFeed::on_estimate(const sphere_estimate_t& m, int64_t now_us) {
  EstimateView e;
  e.window = m.window;
  e.ok = m.ok;
  e.reason = m.reason;
  e.t_s = m.t_s;
  e.position_m = vec(m.position_m);
  e.velocity_m_s = vec(m.velocity_m_s);
  e.points = m.points;
  e.lines = m.lines;
  e.lines_missing = m.lines_missing;
  e.cpu_us = m.cpu_us;
  e.algorithm = m.algorithm;
  e.variant = m.variant;
  state_.on_estimate(e, now_us);
}

void SphereDisplayFeed::on_guidance(const sphere_guidance_t& m, int64_t now_us) {
  GuidanceView g;
  g.t_s = m.t_s;
  g.position_m = vec(m.position_m);
  g.velocity_m_s = vec(m.velocity_m_s);
  g.position_sigma_m = vec(m.position_sigma_m);
  g.velocity_sigma_m_s = vec(m.velocity_sigma_m_s);
  g.chaser_velocity_m_s = vec(m.chaser_velocity_m_s);
  g.range_to_capture_m = m.range_to_capture_m;
  g.phase = m.phase;
  g.estimates_used = m.estimates_used;
  g.estimates_downweighted = m.estimates_downweighted;
  g.estimates_rejected = m.estimates_rejected;
  g.no_estimates = m.no_estimates;
  state_.on_guidance(g, now_us);
}

void SphereDisplayFeed::on_truth(const sphere_truth_t& m, int64_t now_us) {
  TruthView t;
  t.t_s = m.t_s;
  t.approach = m.approach;
  t.phase = m.phase;
  t.position_m = vec(m.position_m);
  t.velocity_m_s = vec(m.velocity_m_s);
  t.capture_t_s = m.capture_t_s;
  t.capture_speed_m_s = m.capture_speed_m_s;
  t.capture_offset_m = m.capture_offset_m;
  t.verdict = m.verdict;
  state_.on_truth(t, now_us);
}

}  // namespace ephor::sphere_display
