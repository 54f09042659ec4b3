#include "common/sphere/scan_file.h"

#include <cerrno>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <istream>
#include <ostream>
#include <sstream>

namespace ephor::sphere {
namespace {

std::string trim(const std::string& s) {
  size_t b = 0, e = s.size();
  while (b < e && (s[b] == ' ' || s[b] == '\t')) ++b;
  while (e > b && (s[e - 1] == ' ' || s[e - 1] == '\t' || s[e - 1] == '\r')) --e;
  return s.substr(b, e - b);
}

[[noreturn]] void refuse(const std::string& name, size_t line_no, const std::string& what) {
  throw ScanFileError(name + ":" + std::to_string(line_no) + ": " + what);
}

bool is_nan_word(const std::string& s) {
  return s == "nan" || s == "NaN" || s == "NAN" || s == "-nan";
}

double parse_number(const std::string& field, const char* column, bool allow_nan,
                    const std::string& name, size_t line_no) {
  const std::string f = trim(field);
  if (allow_nan && is_nan_word(f)) return std::nan("");
  if (f.empty()) refuse(name, line_no, std::string(column) + " is empty");
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(f.c_str(), &end);
  if (end != f.c_str() + f.size() || errno == ERANGE || !std::isfinite(v)) {
    refuse(name, line_no, std::string(column) + " '" + f + "' is not a finite number");
  }
  return v;
}

}  // namespace

std::vector<ScanLine> ScanFile::read(std::istream& in, const std::string& name) {
  std::vector<ScanLine> lines;
  std::string text;
  size_t line_no = 0;
  if (!std::getline(in, text)) refuse(name, 1, "empty file (expected the header)");
  ++line_no;
  if (trim(text) != kHeader) {
    refuse(name, line_no, std::string("header must be '") + kHeader + "'");
  }
  double last_t = -INFINITY;
  while (std::getline(in, text)) {
    ++line_no;
    if (trim(text).empty()) continue;
    std::vector<std::string> fields;
    std::stringstream ss(text);
    std::string field;
    while (std::getline(ss, field, ',')) fields.push_back(field);
    if (!text.empty() && text.back() == ',') fields.emplace_back();
    if (fields.size() != 5) {
      refuse(name, line_no, "expected 5 columns, found " + std::to_string(fields.size()));
    }
    Pulse p;
    p.t_s = parse_number(fields[0], "t_s", false, name, line_no);
    if (std::abs(p.t_s) > kMaxTimeS) {
      refuse(name, line_no,
             "t_s '" + trim(fields[0]) + "' is beyond +-" +
                 std::to_string(static_cast<long long>(kMaxTimeS)) + " s");
    }
    const double line_value = parse_number(fields[1], "line", false, name, line_no);
    if (line_value != std::floor(line_value) || std::abs(line_value) > 9.0e15) {
      refuse(name, line_no, "line '" + trim(fields[1]) + "' is not an integer");
    }
    p.azimuth_rad = parse_number(fields[2], "azimuth_rad", false, name, line_no);
    p.elevation_rad = parse_number(fields[3], "elevation_rad", false, name, line_no);
    p.range_m = parse_number(fields[4], "range_m", true, name, line_no);
    if (std::abs(p.azimuth_rad) > M_PI || std::abs(p.elevation_rad) > M_PI / 2) {
      refuse(name, line_no, "angle out of range (|azimuth| <= pi, |elevation| <= pi/2)");
    }
    if (p.has_range() && p.range_m < 0.0) refuse(name, line_no, "negative range_m");
    if (p.t_s < last_t) {
      refuse(
          name, line_no,
          "time goes backwards (" + trim(fields[0]) + " s after " + std::to_string(last_t) + " s)");
    }
    last_t = p.t_s;
    const auto id = static_cast<int64_t>(line_value);
    if (lines.empty() || lines.back().id != id) lines.push_back(ScanLine{id, {}});
    lines.back().pulses.push_back(p);
  }
  return lines;
}

std::vector<ScanLine> ScanFile::read(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw ScanFileError(path + ": cannot open");
  return read(in, path);
}

void ScanFile::write(std::ostream& out, const std::vector<ScanLine>& lines) {
  out << kHeader << '\n';
  char buf[160];
  for (const ScanLine& line : lines) {
    for (const Pulse& p : line.pulses) {
      if (p.has_range()) {
        std::snprintf(buf, sizeof buf, "%.7f,%" PRId64 ",%.9f,%.9f,%.6f\n", p.t_s, line.id,
                      p.azimuth_rad, p.elevation_rad, p.range_m);
      } else {
        std::snprintf(buf, sizeof buf, "%.7f,%" PRId64 ",%.9f,%.9f,nan\n", p.t_s, line.id,
                      p.azimuth_rad, p.elevation_rad);
      }
      out << buf;
    }
  }
}

void ScanFile::write(const std::string& path, const std::vector<ScanLine>& lines) {
  std::ofstream out(path);
  if (!out) throw ScanFileError(path + ": cannot write");
  write(out, lines);
  if (!out) throw ScanFileError(path + ": write failed");
}

std::vector<Window> split_windows(const std::vector<ScanLine>& lines, double window_s) {
  if (!(window_s > 0.0)) throw std::invalid_argument("split_windows: window must be > 0 s");
  std::vector<Window> windows;
  for (const ScanLine& line : lines) {
    for (const Pulse& p : line.pulses) {
      if (p.t_s < 0.0) continue;  // windows start at t = 0
      const double kd = std::floor(p.t_s / window_s);
      if (!(kd < kMaxWindows))
        throw std::invalid_argument("split_windows: a pulse at " + std::to_string(p.t_s) +
                                    " s would need more than " +
                                    std::to_string(static_cast<long long>(kMaxWindows)) +
                                    " windows of " + std::to_string(window_s) + " s");
      const auto k = static_cast<size_t>(kd);
      while (windows.size() <= k) {
        Window w;
        w.t_begin_s = static_cast<double>(windows.size()) * window_s;
        w.t_end_s = w.t_begin_s + window_s;
        windows.push_back(std::move(w));
      }
      Window& w = windows[k];
      if (w.lines.empty() || w.lines.back().id != line.id) w.lines.push_back(ScanLine{line.id, {}});
      w.lines.back().pulses.push_back(p);
    }
  }
  return windows;
}

}  // namespace ephor::sphere
