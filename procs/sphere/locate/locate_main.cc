// ephor-sphere-locate: locate the sphere in a recorded scan file (paper 002),
// one estimate per window [k W, (k+1) W) from t = 0, each independent.
//
//   ephor-sphere-locate SCAN.csv --algorithm sle|fit [--variant paper|improved]
//                       [--window-s 0.5] [--background-m 50] --json OUT
//
// OUT (JSON Lines, '-' = stdout), one line per window:
//   {"t_s": T, "position_m": [x, y, z], "velocity_m_s": [vx, vy, vz],
//    "points": n, "lines": m, "cpu_us": c, "window_s": [b, e]}
// or, when the window has no usable sphere,
//   {"t_s": b, "estimate": "no estimate", "reason": "...", "points": n, ...}
// Sensor frame of eq. 35-37 (X right, Y up, Z along the boresight), metres.
// Exit status 2 for a bad flag or a malformed scan file (the line is named).

#include <fstream>
#include <iostream>
#include <string>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "common/sphere/scan_file.h"
#include "common/sphere/sphere_locator.h"

int main(int argc, char** argv) {
  using namespace ephor::sphere;
  CLI::App app{"ephor-sphere-locate: the sphere's position per window of a recorded scan"};
  std::string scan_path, json_path, algorithm = "sle", variant = "improved";
  double window_s = 0.5, background_m = 50.0;
  app.add_option("scan", scan_path, "scan CSV (t_s,line,azimuth_rad,elevation_rad,range_m)")
      ->required();
  app.add_option("--algorithm", algorithm, "sle (Scan Line Extent) or fit (Sphere Fitting)")
      ->check(CLI::IsMember({"sle", "fit"}));
  app.add_option("--variant", variant, "paper (as published) or improved (bias corrections)")
      ->check(CLI::IsMember({"paper", "improved"}));
  app.add_option("--window-s", window_s, "window length, s")->check(CLI::Range(0.01, 3600.0));
  app.add_option("--background-m", background_m, "returns at or beyond this range are background")
      ->check(CLI::Range(0.2, 1e6));
  app.add_option("--json", json_path, "output, one JSON line per window ('-' = stdout)")
      ->required();
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "ephor-sphere-locate: " << e.what() << "\n";
    return 2;
  }
  try {
    const std::vector<ScanLine> lines = ScanFile::read(scan_path);
    LocatorConfig cfg;
    cfg.algorithm = parse_algorithm(algorithm);
    cfg.variant = parse_variant(variant);
    cfg.background_range_m = background_m;
    const SphereLocator locator(cfg);
    std::ofstream file;
    if (json_path != "-") {
      file.open(json_path);
      if (!file) throw std::runtime_error("cannot write '" + json_path + "'");
    }
    std::ostream& out = json_path == "-" ? std::cout : file;
    int estimates = 0, none = 0;
    for (const Window& w : split_windows(lines, window_s)) {
      double cpu_us = 0.0;
      const Estimate e = locator.locate(w, &cpu_us);
      nlohmann::json j;
      if (e.ok) {
        j["t_s"] = e.t_s;
        j["position_m"] = {e.position_m.x(), e.position_m.y(), e.position_m.z()};
        j["velocity_m_s"] = {e.velocity_m_s.x(), e.velocity_m_s.y(), e.velocity_m_s.z()};
        ++estimates;
      } else {
        j["t_s"] = w.t_begin_s;
        j["estimate"] = "no estimate";
        j["reason"] = e.reason.empty() ? "no scan lines in the window" : e.reason;
        ++none;
      }
      j["points"] = e.points;
      j["lines"] = e.lines;
      j["cpu_us"] = cpu_us;
      j["window_s"] = {w.t_begin_s, w.t_end_s};
      out << j.dump() << "\n";
    }
    std::cerr << "ephor-sphere-locate: " << estimates << " estimates, " << none
              << " windows with no estimate (" << to_string(cfg.algorithm) << ", "
              << to_string(cfg.variant) << ")\n";
  } catch (const ScanFileError& e) {
    std::cerr << "ephor-sphere-locate: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "ephor-sphere-locate: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
