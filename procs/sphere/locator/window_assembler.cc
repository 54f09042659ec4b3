#include "procs/sphere/locator/window_assembler.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>

namespace ephor::sphere {

WindowAssembler::WindowAssembler(double window_s) : window_s_(window_s) {
  if (!(window_s > 0.0 && window_s <= 60.0)) {
    throw std::invalid_argument("window must be in (0, 60] s");
  }
}

int64_t WindowAssembler::index_of(double t_s) const {
  // A pulse exactly on a boundary (to rounding) belongs to the later window.
  return static_cast<int64_t>(std::floor(t_s / window_s_ + 1e-9));
}

WindowAssembler::Open& WindowAssembler::open_window(int64_t k) {
  auto [it, inserted] = open_.try_emplace(k);
  if (inserted) {
    it->second.window.t_begin_s = static_cast<double>(k) * window_s_;
    it->second.window.t_end_s = static_cast<double>(k + 1) * window_s_;
  }
  return it->second;
}

std::string WindowAssembler::add(const LineMessage& m) {
  auto refuse = [this](std::string why) {
    ++refused_;
    return why;
  };
  const size_t n = m.num_pulses < 0 ? 0 : static_cast<size_t>(m.num_pulses);
  if (m.num_pulses < 0 || m.t_s.size() != n || m.azimuth_rad.size() != n ||
      m.elevation_rad.size() != n || m.range_m.size() != n) {
    return refuse("line " + std::to_string(m.line) + ": " + std::to_string(m.num_pulses) +
                  " pulses but arrays of " + std::to_string(m.t_s.size()) + ", " +
                  std::to_string(m.azimuth_rad.size()) + ", " +
                  std::to_string(m.elevation_rad.size()) + ", " + std::to_string(m.range_m.size()));
  }
  if (n == 0) return refuse("line " + std::to_string(m.line) + ": no pulses");
  for (size_t i = 0; i < n; ++i) {
    const std::string at = "line " + std::to_string(m.line) + " pulse " + std::to_string(i) + ": ";
    if (!std::isfinite(m.t_s[i]) || m.t_s[i] < 0.0) return refuse(at + "time not finite or < 0");
    // Beyond it the window index would leave int64's range (UB): 3 years of
    // a ranger's scan clock (s since it started).
    if (m.t_s[i] > kMaxScanTimeS)
      return refuse(at + "time beyond " + std::to_string(kMaxScanTimeS) + " s of scan clock");
    if (i > 0 && m.t_s[i] < m.t_s[i - 1]) return refuse(at + "time goes backwards");
    if (!(std::abs(m.azimuth_rad[i]) <= M_PI) || !(std::abs(m.elevation_rad[i]) <= M_PI)) {
      return refuse(at + "angle not finite or beyond +-pi");
    }
    if (m.range_m[i] < 0.0 || std::isinf(m.range_m[i])) {
      return refuse(at + "range negative or infinite");
    }
  }
  const int64_t first = index_of(m.t_s.front());
  if (first < emitted_up_to_ - kRestartWindows && m.line < last_line_) {
    // Far back in time and in the line counter: the ranger started again
    // (its scan clock and counter restart at 0). Its windows are new ones;
    // refusing them as late would blind the locator until the new clock
    // caught up with the old one.
    open_.clear();
    emitted_up_to_ = -1;
    ++restarts_;
  }
  last_line_ = m.line;
  if (first <= emitted_up_to_) {
    ++late_;
    return refuse("line " + std::to_string(m.line) + ": late, window " + std::to_string(first) +
                  " was already located");
  }
  // Split by pulse time into windows.
  size_t i = 0;
  while (i < n) {
    const int64_t k = index_of(m.t_s[i]);
    Open& w = open_window(k);
    ScanLine line;
    line.id = m.line;
    for (; i < n && index_of(m.t_s[i]) == k; ++i) {
      Pulse p;
      p.t_s = m.t_s[i];
      p.azimuth_rad = m.azimuth_rad[i];
      p.elevation_rad = m.elevation_rad[i];
      p.range_m = m.range_m[i];
      line.pulses.push_back(p);
    }
    w.window.lines.push_back(std::move(line));
    w.min_line = std::min(w.min_line, m.line);
    w.max_line = std::max(w.max_line, m.line);
    ++w.lines;
  }
  const int64_t last = index_of(m.t_s.back());
  // A pulse of window `last` completes every earlier window.
  for (auto& [k, w] : open_) {
    if (k < last) w.complete = true;
  }
  // The ranger's own end-of-window mark, when its windows are ours.
  if (m.last_in_window && std::abs(m.window_s - window_s_) < 1e-9) {
    const double end = static_cast<double>(last + 1) * window_s_;
    // Its last pulse lies within one pulse spacing of the end of our window.
    if (end - m.t_s.back() < 0.01 * window_s_) open_window(last).complete = true;
  }
  return "";
}

AssembledWindow WindowAssembler::finish(int64_t k, Open& w) const {
  AssembledWindow a;
  a.index = k;
  a.lines_received = w.lines;
  // In double and clamped: a corrupt line counter far from the others made
  // the span overflow int and the count negative (fuzz_sphere_scan_line), and
  // counters 2^63 apart would overflow int64.
  const double span = static_cast<double>(w.max_line) - static_cast<double>(w.min_line) + 1.0;
  a.lines_missing =
      w.lines > 0
          ? static_cast<int>(std::clamp(span - w.lines, 0.0, static_cast<double>(INT32_MAX)))
          : 0;
  a.window = std::move(w.window);
  return a;
}

std::vector<AssembledWindow> WindowAssembler::take_complete() {
  std::vector<AssembledWindow> out;
  for (auto it = open_.begin(); it != open_.end() && it->second.complete;) {
    out.push_back(finish(it->first, it->second));
    emitted_up_to_ = it->first;
    it = open_.erase(it);
  }
  return out;
}

std::vector<AssembledWindow> WindowAssembler::flush() {
  std::vector<AssembledWindow> out;
  for (auto& [k, w] : open_) {
    out.push_back(finish(k, w));
    emitted_up_to_ = k;
  }
  open_.clear();
  return out;
}

}  // namespace ephor::sphere
