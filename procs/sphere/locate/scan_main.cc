// ephor-sphere-scan: write the paper's simulated trials (section 4) as a scan
// file for ephor-sphere-locate, and their truth.
//
//   ephor-sphere-scan --distance-m 5 [--seed 1] [--trials N] [--trial-s 0.5]
//                     [--background-below-deg E] [--range-sigma-m 0.02]
//                     [--angle-sigma-rad 0.00078] --out scan.csv [--truth truth.jsonl]
//
// Trial k covers [k T, (k+1) T): the raster restarts at the upper left, the
// sphere's centre passes (0, 0, distance) at (k + 0.5) T moving at Table 1's
// speeds (up, right, toward the sensor). --truth writes one JSON line per
// trial: {"trial", "t0_s", "position_m" (at t0_s), "velocity_m_s", "half_extent_deg"}.

#include <fstream>
#include <iostream>
#include <string>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "common/sphere/range_simulator.h"
#include "common/sphere/scan_file.h"

int main(int argc, char** argv) {
  using namespace ephor::sphere;
  CLI::App app{"ephor-sphere-scan: simulated scans of the paper's trials as a scan file"};
  double distance_m = 5.0, trial_s = 0.5, range_sigma = 0.02, angle_sigma = 0.78e-3;
  double background_below_deg = 0.0;
  bool background = false;
  uint64_t seed = 1;
  int trials = 1;
  std::string out_path, truth_path;
  app.add_option("--distance-m", distance_m, "distance to the sphere, m")
      ->check(CLI::Range(0.2, 1000.0));
  app.add_option("--seed", seed, "noise seed");
  app.add_option("--trials", trials, "number of consecutive trials")->check(CLI::Range(1, 100000));
  app.add_option("--trial-s", trial_s, "trial length, s")->check(CLI::Range(0.01, 60.0));
  app.add_option("--range-sigma-m", range_sigma, "range noise sigma, m")
      ->check(CLI::Range(0.0, 10.0));
  app.add_option("--angle-sigma-rad", angle_sigma, "encoder noise sigma, rad")
      ->check(CLI::Range(0.0, 0.1));
  app.add_option("--background-below-deg", background_below_deg,
                 "a wall at 60 m behind pulses lower than this elevation")
      ->check(CLI::Range(-90.0, 90.0))
      ->each([&](const std::string&) { background = true; });
  app.add_option("--out", out_path, "scan CSV to write")->required();
  app.add_option("--truth", truth_path, "truth, one JSON line per trial");
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "ephor-sphere-scan: " << e.what() << "\n";
    return 2;
  }
  try {
    std::vector<ScanLine> all;
    std::ofstream truth;
    if (!truth_path.empty()) {
      truth.open(truth_path);
      if (!truth) throw std::runtime_error("cannot write '" + truth_path + "'");
    }
    int64_t next_line = 0;
    for (int k = 0; k < trials; ++k) {
      const double t0 = k * trial_s;
      RangeSimulatorConfig c = RangeSimulator::paper_trial(
          distance_m, seed * 100003ULL + static_cast<uint64_t>(k), t0, trial_s);
      c.noise = {range_sigma, angle_sigma};
      c.background.enabled = background;
      c.background.below_elevation_deg = background_below_deg;
      RangeSimulator sim(c);
      std::vector<ScanLine> lines = sim.scan(t0, trial_s, next_line);
      if (!lines.empty()) next_line = lines.back().id + 1;
      for (ScanLine& l : lines) all.push_back(std::move(l));
      if (truth) {
        const Eigen::Vector3d p = c.sphere.centre_at(t0);
        nlohmann::json j = {
            {"trial", k},
            {"t0_s", t0},
            {"position_m", {p.x(), p.y(), p.z()}},
            {"velocity_m_s",
             {c.sphere.velocity_m_s.x(), c.sphere.velocity_m_s.y(), c.sphere.velocity_m_s.z()}},
            {"half_extent_deg", c.scanner.half_extent_deg}};
        truth << j.dump() << "\n";
      }
    }
    ScanFile::write(out_path, all);
  } catch (const std::exception& e) {
    std::cerr << "ephor-sphere-scan: " << e.what() << "\n";
    return 2;
  }
  return 0;
}
