#pragma once
// Cuts the ranger's stream of scan lines into the locator's windows
// [kW, (k+1)W) of the scan clock (issue 15: "every half second, from the
// newest half-second of lines"), checking every line on the way in: a line
// with non-finite or backward times, angles beyond +-pi, a negative range,
// or arrays whose lengths disagree with its count, or a time beyond
// kMaxScanTimeS, is refused with the reason, never passed on.
//
// A window is complete when the ranger says its last line has come
// (last_in_window, with the same window length) or when a pulse of a later
// window arrives (the flag's message was lost). Lines are assigned by
// their pulses' times, so a locator whose --window-s differs from the
// ranger's still gets [kW, (k+1)W) (lines that straddle a boundary are split).
// A line one to kRestartWindows windows behind the newest window located is
// late and refused; further back, with the line counter gone back too, the
// ranger has restarted and the assembler starts over.

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "common/sphere/scan_types.h"

namespace ephor::sphere {

// One scan line as it arrives (the fields of sphere_scan_line_t).
struct LineMessage {
  int64_t line = 0;
  int64_t window = 0;
  double window_s = 0.0;
  bool last_in_window = false;
  int32_t num_pulses = 0;
  std::vector<double> t_s, azimuth_rad, elevation_rad, range_m;
};

struct AssembledWindow {
  int64_t index = 0;  // k
  Window window;      // [kW, (k+1)W), lines in arrival order
  int lines_received = 0;
  int lines_missing = 0;  // gaps in the line counter between the window's first and last line
};

class WindowAssembler {
 public:
  // Throws std::invalid_argument unless 0 < window_s <= 60.
  explicit WindowAssembler(double window_s);

  // Adds a line; returns "" when accepted, else why it was refused.
  std::string add(const LineMessage& m);

  // The windows completed so far, oldest first; each is returned once.
  std::vector<AssembledWindow> take_complete();
  // Every window still open (the stream has ended).
  std::vector<AssembledWindow> flush();

  double window_s() const { return window_s_; }
  int64_t refused() const { return refused_; }
  int64_t late() const { return late_; }
  // Times the scan clock and line counter went back by more than
  // kRestartWindows windows (a restarted ranger): the assembler starts over.
  int64_t restarts() const { return restarts_; }
  static constexpr int64_t kRestartWindows = 4;
  // Pulse times beyond this (s of scan clock, 3 years) are refused.
  static constexpr double kMaxScanTimeS = 1e8;

 private:
  struct Open {
    Window window;
    int64_t min_line = INT64_MAX, max_line = INT64_MIN;
    int lines = 0;
    bool complete = false;
  };
  int64_t index_of(double t_s) const;
  Open& open_window(int64_t k);
  AssembledWindow finish(int64_t k, Open& w) const;

  double window_s_;
  std::map<int64_t, Open> open_;
  int64_t emitted_up_to_ = -1;     // windows <= this were returned
  int64_t last_line_ = INT64_MIN;  // the newest accepted line's counter
  int64_t refused_ = 0, late_ = 0, restarts_ = 0;
};

}  // namespace ephor::sphere
