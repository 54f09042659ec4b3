#include "procs/sphere/locator/line_message.h"

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

}  // namespace ephor::sphere
