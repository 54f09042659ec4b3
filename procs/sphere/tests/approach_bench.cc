// ephor-bench-sphere-approach: the sphere system's approach flown many
// times without LCM (approach_sim.h: the ranger's world, the locator and
// the guidance with the processes' timing), one line per seed and a
// summary: how many captured, time to capture, relative speed and offset
// at capture, the locator's and the filter's error against the truth.
//
//   ephor-bench-sphere-approach [--seeds 20] [--start-m 20] [--algorithm sle|fit]
//                               [--variant paper|improved] [--json FILE] [--verbose-seed S]

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "common/runtime/process_args.h"
#include "procs/sphere/tests/approach_sim.h"

using namespace ephor::sphere;

int main(int argc, char** argv) {
  CLI::App app{"ephor-bench-sphere-approach: seeded approaches from the start distance to capture"};
  int seeds = 20;
  int64_t first_seed = 1, verbose_seed = -1;
  double start_m = 20.0, max_s = 300.0;
  std::string algorithm = "sle", variant = "improved", json_path;
  bool background = false;
  app.add_option("--seeds", seeds, "approaches, seeds first..first+n-1 (default 20)")
      ->check(CLI::Range(1, 100000));
  app.add_option("--first-seed", first_seed, "first seed (default 1)");
  app.add_option("--start-m", start_m, "start distance (m, default 20)")
      ->check(CLI::Range(1.05, 5000.0));
  app.add_option("--max-s", max_s, "give up after (s, default 300)")->check(CLI::Range(1.0, 1e5));
  app.add_option("--algorithm", algorithm, "sle or fit");
  app.add_option("--variant", variant, "paper or improved");
  app.add_flag("--background", background, "far wall behind the lower half of the frame");
  app.add_option("--json", json_path, "write the results here");
  app.add_option("--verbose-seed", verbose_seed, "print every window of this seed");
  if (const auto exit_status = ephor::parse_flags(app, argc, argv)) return *exit_status;
  LocatorConfig lc;
  try {
    lc.algorithm = parse_algorithm(algorithm);
    lc.variant = parse_variant(variant);
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  }

  nlohmann::json runs = nlohmann::json::array();
  int captured = 0;
  std::vector<double> times, speeds, offsets;
  std::printf(
      "seed  verdict       t_s  speed_cm_s  offset_cm  est_rms_mm(x,y,z)   filt_rms_mm(x,y,z)  "
      "rejected\n");
  for (int i = 0; i < seeds; ++i) {
    const auto seed = static_cast<uint64_t>(first_seed + i);
    ApproachSimConfig c = approach_sim_config(seed, start_m, max_s);
    c.locator = lc;
    c.world.background.enabled = background;
    c.verbose = static_cast<int64_t>(seed) == verbose_seed;
    const ApproachResult r = fly_approach(c);
    const bool ok = r.judged && r.verdict.captured;
    captured += ok ? 1 : 0;
    if (r.judged) {
      times.push_back(r.verdict.t_s);
      speeds.push_back(r.verdict.speed_m_s);
      offsets.push_back(r.verdict.offset_m);
    }
    std::printf(
        "%4llu  %-12s %6.1f  %10.2f  %9.2f  %5.1f %5.1f %5.1f   %5.1f %5.1f %5.1f  %3d %3d\n",
        static_cast<unsigned long long>(seed), ok ? "captured" : "not captured", r.verdict.t_s,
        r.verdict.speed_m_s * 100, r.verdict.offset_m * 100, r.estimate_rms_m[0] * 1e3,
        r.estimate_rms_m[1] * 1e3, r.estimate_rms_m[2] * 1e3, r.filter_rms_m[0] * 1e3,
        r.filter_rms_m[1] * 1e3, r.filter_rms_m[2] * 1e3, r.downweighted, r.rejected);
    if (!ok) std::printf("      %s\n", r.verdict.text.c_str());
    runs.push_back(
        {{"seed", seed},
         {"captured", ok},
         {"verdict", r.verdict.text},
         {"t_s", r.verdict.t_s},
         {"speed_m_s", r.verdict.speed_m_s},
         {"offset_m", r.verdict.offset_m},
         {"estimates", r.estimates},
         {"no_estimates", r.no_estimates},
         {"rejected", r.rejected},
         {"downweighted", r.downweighted},
         {"reinitialised", r.reinitialised},
         {"estimate_rms_m", {r.estimate_rms_m[0], r.estimate_rms_m[1], r.estimate_rms_m[2]}},
         {"filter_rms_m", {r.filter_rms_m[0], r.filter_rms_m[1], r.filter_rms_m[2]}},
         {"estimate_cpu_us_max", r.estimate_cpu_us_max}});
  }
  auto maxof = [](const std::vector<double>& v) {
    return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end());
  };
  auto median = [](std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
  };
  std::printf(
      "captured %d of %d from %.1f m (%s, %s): time to capture median %.1f s, max %.1f s; speed "
      "at capture median %.2f cm/s, max %.2f; offset median %.2f cm, max %.2f (limits 2 cm/s, 2 "
      "cm)\n",
      captured, seeds, start_m, algorithm.c_str(), variant.c_str(), median(times), maxof(times),
      median(speeds) * 100, maxof(speeds) * 100, median(offsets) * 100, maxof(offsets) * 100);
  if (!json_path.empty()) {
    nlohmann::json j = {{"start_m", start_m},
                        {"algorithm", algorithm},
                        {"variant", variant},
                        {"background", background},
                        {"seeds", seeds},
                        {"captured", captured},
                        {"time_s_median", median(times)},
                        {"time_s_max", maxof(times)},
                        {"speed_m_s_max", maxof(speeds)},
                        {"offset_m_max", maxof(offsets)},
                        {"runs", runs}};
    std::ofstream(json_path) << j.dump(2) << "\n";
  }
  return captured == seeds ? 0 : 1;
}
