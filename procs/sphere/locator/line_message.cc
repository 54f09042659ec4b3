#include "procs/sphere/locator/line_message.h"

#include <limits>

namespace ephor::sphere {

LineMessage line_message_of(const sphere_scan_line_t& m) {
  LineMessage l;
  l.line = m.line;
  l.window = m.window;
  l.window_s = m.window_s;
  l.last_in_window = m.last_in_window;
  l.num_pulses = m.num_pulses;
  l.t_s = m.t_s;
  l.azimuth_rad = m.azimuth_rad;
  l.elevation_rad = m.elevation_rad;
  l.range_m = m.range_m;
  return l;
}

sphere_estimate_t estimate_message_of(const Estimate& e, const AssembledWindow& w,
                                      const LocatorConfig& config) {
  sphere_estimate_t m{};
  m.window = w.index;
  m.window_begin_s = w.window.t_begin_s;
  m.window_end_s = w.window.t_end_s;
  m.ok = e.ok;
  m.reason = e.reason;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  m.t_s = e.ok ? e.t_s : nan;
  for (int i = 0; i < 3; ++i) {
    m.position_m[i] = e.ok ? e.position_m[i] : nan;
    m.velocity_m_s[i] = e.ok ? e.velocity_m_s[i] : nan;
  }
  m.points = e.points;
  m.lines = e.lines;
  m.lines_received = w.lines_received;
  m.lines_missing = w.lines_missing;
  m.algorithm = to_string(config.algorithm);
  m.variant = to_string(config.variant);
  return m;
}

}  // namespace ephor::sphere
