#pragma once
// Scan files: the recorded form of a range scan (issue 15, "the offline
// locator"). CSV with the header `t_s,line,azimuth_rad,elevation_rad,range_m`
// and one row per pulse; `line` changes when a new scan line starts;
// `range_m` is `nan` when the pulse hit nothing. Bad rows are refused with
// the file's line number; nothing is guessed.

#include <iosfwd>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/sphere/scan_types.h"

namespace ephor::sphere {

// "NAME:LINE: problem" for a malformed scan file.
class ScanFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class ScanFile {
 public:
  static constexpr const char* kHeader = "t_s,line,azimuth_rad,elevation_rad,range_m";
  // Pulse times are from the scan's start: |t_s| beyond this is refused (a
  // time of 1e46 s once made split_windows cast out of range; issue 18).
  static constexpr double kMaxTimeS = 1.0e5;

  // Rows grouped into lines (consecutive rows with the same `line`). Throws
  // ScanFileError for a missing/wrong header, a wrong column count, a field
  // that is not a number (`nan` is allowed in range_m only), a non-integer
  // line, an angle beyond +-pi, a negative range, a time beyond +-kMaxTimeS,
  // or a time going backwards.
  static std::vector<ScanLine> read(std::istream& in, const std::string& name = "scan");
  static std::vector<ScanLine> read(const std::string& path);

  static void write(std::ostream& out, const std::vector<ScanLine>& lines);
  static void write(const std::string& path, const std::vector<ScanLine>& lines);
};

// Cuts lines into the windows [k W, (k+1) W), k = 0, 1, ... up to the last
// pulse (a line that straddles a boundary is split by pulse time; empty
// windows between pulses are kept, so the k-th window is always [kW,(k+1)W)).
// Throws std::invalid_argument for a window that is not > 0 s, or when the
// pulses would span more than kMaxWindows windows (memory, not a scan).
inline constexpr double kMaxWindows = 1.0e6;
std::vector<Window> split_windows(const std::vector<ScanLine>& lines, double window_s);

}  // namespace ephor::sphere
