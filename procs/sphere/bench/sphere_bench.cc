// ephor-bench-sphere: the paper's results (paper 002, section 5) reproduced
// on this machine, beside its figures (paper_figures.h):
//   - Table 2 from the scanner geometry;
//   - Figures 3 and 4 as tables: bias and sigma per axis, N trials x 6
//     distances, Sphere Fitting and Scan Line Extent;
//   - Figure 5: Scan Line Extent's velocity error;
//   - Tables 3 and 4: min and max CPU time per trial;
//   - the corrections beyond the paper one at a time (what each gains).
// Errors are estimate - truth, truth taken at the time the estimate is for
// (the paper's footnote 1). "sigma" is the paper's eq. 11 (RMS about the
// truth, bias included); "std" is the spread about the bias.
//
//   ephor-bench-sphere [--json FILE] [--trials 200] [--seed 1]

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "common/sphere/range_simulator.h"
#include "common/sphere/scan_line_extent.h"
#include "common/sphere/sphere_fitter.h"
#include "procs/sphere/bench/paper_figures.h"
#include "procs/sphere/bench/pcl_sphere_peer.h"

namespace ephor::sphere {
namespace {

double thread_cpu_us() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) * 1e6 + static_cast<double>(ts.tv_nsec) * 1e-3;
}

struct Method {
  std::string name;
  std::string family;  // "sle", "fit" or "peer"
  std::function<Estimate(const Window&)> locate;
};

struct Tally {
  std::vector<Eigen::Vector3d> pos_err, vel_err;
  std::vector<double> cpu_us;
  int no_estimate = 0;
  std::string last_reason;
};

nlohmann::json summarise(const Tally& t) {
  nlohmann::json j;
  const auto n = static_cast<double>(t.pos_err.size());
  j["estimates"] = t.pos_err.size();
  j["no_estimate"] = t.no_estimate;
  if (t.no_estimate > 0) j["no_estimate_reason"] = t.last_reason;
  if (t.pos_err.empty()) return j;
  auto stats = [&](const std::vector<Eigen::Vector3d>& errs, const char* prefix) {
    Eigen::Vector3d mean = Eigen::Vector3d::Zero(), ms = Eigen::Vector3d::Zero();
    for (const auto& e : errs) {
      mean += e;
      ms += e.cwiseProduct(e);
    }
    mean /= n;
    ms /= n;
    const Eigen::Vector3d rms = ms.cwiseSqrt();
    const Eigen::Vector3d sd = (ms - mean.cwiseProduct(mean)).cwiseMax(0.0).cwiseSqrt();
    j[std::string(prefix) + "bias"] = {mean.x(), mean.y(), mean.z()};
    j[std::string(prefix) + "sigma"] = {rms.x(), rms.y(), rms.z()};
    j[std::string(prefix) + "std"] = {sd.x(), sd.y(), sd.z()};
  };
  stats(t.pos_err, "position_m_");
  if (!t.vel_err.empty()) stats(t.vel_err, "velocity_m_s_");  // the static peer has none
  j["cpu_us_min"] = *std::min_element(t.cpu_us.begin(), t.cpu_us.end());
  j["cpu_us_max"] = *std::max_element(t.cpu_us.begin(), t.cpu_us.end());
  std::vector<double> c = t.cpu_us;
  std::nth_element(c.begin(), c.begin() + static_cast<std::ptrdiff_t>(c.size() / 2), c.end());
  j["cpu_us_median"] = c[c.size() / 2];
  return j;
}

std::vector<Method> methods() {
  std::vector<Method> m;
  auto sle = [&](const std::string& name, ScanLineExtentConfig c) {
    m.push_back({name, "sle", [s = ScanLineExtent(c)](const Window& w) { return s.locate(w); }});
  };
  auto fit = [&](const std::string& name, SphereFitterConfig c) {
    m.push_back({name, "fit", [f = SphereFitter(c)](const Window& w) { return f.locate(w); }});
  };
  ScanLineExtentConfig s = ScanLineExtentConfig::paper();
  sle("sle-paper", s);
  s.edge_correction = true;
  sle("sle+edge", s);
  s.exact_geometry = true;
  sle("sle+edge+geometry", s);
  s.weighted_regression = true;
  sle("sle+edge+geometry+weights", s);
  ScanLineExtentConfig per_line_slope = ScanLineExtentConfig::improved();
  per_line_slope.window_slope = false;
  sle("sle-improved-per-line-slope", per_line_slope);
  sle("sle-improved", ScanLineExtentConfig::improved());
  fit("fit-paper", SphereFitterConfig::paper());
  SphereFitterConfig f = SphereFitterConfig::paper();
  f.residual = FitResidual::kGeometricWeighted;
  f.noise_offset_correction = false;
  fit("fit-geometric-weighted", f);
  f.noise_offset_correction = true;
  fit("fit-geometric-weighted+offset", f);
  fit("fit-improved", SphereFitterConfig::improved());
  if (pcl_peer_available()) {
    m.push_back(
        {"pcl-ransac-sphere", "peer", [](const Window& w) { return pcl_sphere_locate(w); }});
  }
  return m;
}

void print_table(const nlohmann::json& results, const std::vector<Method>& ms,
                 const std::vector<double>& distances, int trials) {
  std::printf(
      "\nPosition error, mm (bias / sigma eq. 11), %d trials per distance; error = estimate - "
      "truth\n",
      trials);
  for (const Method& m : ms) {
    std::printf("%-28s", m.name.c_str());
    for (double d : distances) std::printf(" | %5.0f m: x        y        z      ", d);
    std::printf("\n%-28s", "");
    for (double d : distances) {
      const auto& j = results[m.name][std::to_string(static_cast<int>(d))];
      if (!j.contains("position_m_bias")) {
        std::printf(" | %-40s", "no estimates");
        continue;
      }
      std::printf(" | ");
      for (int a = 0; a < 3; ++a) {
        std::printf("%+5.1f/%4.1f ", 1e3 * j["position_m_bias"][a].get<double>(),
                    1e3 * j["position_m_sigma"][a].get<double>());
      }
    }
    std::printf("\n");
  }
  std::printf("\nCPU per trial, us (min / median / max) and velocity sigma, mm/s (x y z)\n");
  for (const Method& m : ms) {
    std::printf("%-28s", m.name.c_str());
    for (double d : distances) {
      const auto& j = results[m.name][std::to_string(static_cast<int>(d))];
      if (!j.contains("cpu_us_min")) continue;
      if (!j.contains("velocity_m_s_sigma")) {
        std::printf(" | %.0f/%.0f/%.0f v -", j["cpu_us_min"].get<double>(),
                    j["cpu_us_median"].get<double>(), j["cpu_us_max"].get<double>());
        continue;
      }
      std::printf(" | %.0f/%.0f/%.0f v %.0f %.0f %.0f", j["cpu_us_min"].get<double>(),
                  j["cpu_us_median"].get<double>(), j["cpu_us_max"].get<double>(),
                  1e3 * j["velocity_m_s_sigma"][0].get<double>(),
                  1e3 * j["velocity_m_s_sigma"][1].get<double>(),
                  1e3 * j["velocity_m_s_sigma"][2].get<double>());
    }
    std::printf("\n");
  }
}

}  // namespace
}  // namespace ephor::sphere

int main(int argc, char** argv) {
  using namespace ephor::sphere;
  CLI::App app{"ephor-bench-sphere: the paper's tables and figures on this machine"};
  std::string json_path;
  int trials = 200;
  uint64_t seed = 1;
  std::vector<double> distances(std::begin(paper::kDistancesM), std::end(paper::kDistancesM));
  app.add_option("--json", json_path, "write the results as JSON");
  app.add_option("--trials", trials, "trials per distance")->check(CLI::Range(1, 100000));
  app.add_option("--seed", seed, "first noise seed");
  std::string only;
  double pulse_rate_hz = 10000.0;
  app.add_option("--pulse-rate-hz", pulse_rate_hz,
                 "laser pulse rate (the paper prints \"10000 MHz\"; 10 kHz by default)")
      ->check(CLI::Range(100.0, 1e7));
  app.add_option("--distances", distances, "distances, m (default the paper's six)");
  app.add_option("--only", only, "run only the methods whose name contains this");
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "ephor-bench-sphere: " << e.what() << "\n";
    return 2;
  }

  nlohmann::json out;
  // Table 2 from the scanner geometry, beside the paper's.
  std::printf("Table 2: half angular extent (deg) and frames per trial, ours / paper\n");
  for (int i = 0; i < 6; ++i) {
    const double d = paper::kDistancesM[i];
    const RangeSimulatorConfig c = RangeSimulator::paper_trial(d, 1);
    const double frames = RasterScanner(c.scanner).frames_in(0.5);
    std::printf(
        "  %4.0f m: %.4f / %.2f   %.4f / %.2f   (x/y speed %.1f cm/s; Table 1 prints %.1f)\n", d,
        c.scanner.half_extent_deg, paper::kTable2HalfExtentDeg[i], frames, paper::kTable2Frames[i],
        100 * table1_xy_speed_m_s(d), paper::kTable1TotalCmS[i]);
    out["table2"].push_back({{"distance_m", d},
                             {"half_extent_deg", c.scanner.half_extent_deg},
                             {"paper_half_extent_deg", paper::kTable2HalfExtentDeg[i]},
                             {"frames_per_trial", frames},
                             {"paper_frames_per_trial", paper::kTable2Frames[i]},
                             {"xy_speed_m_s", table1_xy_speed_m_s(d)},
                             {"paper_table1_xy_speed_m_s", paper::kTable1TotalCmS[i] / 100}});
  }

  std::vector<Method> ms = methods();
  if (!only.empty()) {
    std::erase_if(ms, [&](const Method& m) { return m.name.find(only) == std::string::npos; });
  }
  std::map<std::string, std::map<int, Tally>> tallies;
  for (double d : distances) {
    for (int k = 0; k < trials; ++k) {
      RangeSimulatorConfig config =
          RangeSimulator::paper_trial(d, seed + static_cast<uint64_t>(k) * 7919ULL);
      config.scanner.pulse_rate_hz = pulse_rate_hz;
      RangeSimulator sim(config);
      const Window w{0.0, 0.5, sim.scan(0.0, 0.5)};
      const SphereTrajectory& truth = sim.config().sphere;
      for (const Method& m : ms) {
        const double t0 = thread_cpu_us();
        const Estimate e = m.locate(w);
        const double cpu = thread_cpu_us() - t0;
        Tally& t = tallies[m.name][static_cast<int>(d)];
        if (!e.ok) {
          ++t.no_estimate;
          t.last_reason = e.reason;
          continue;
        }
        t.pos_err.push_back(e.position_m - truth.centre_at(e.t_s));
        if (m.family != "peer") t.vel_err.push_back(e.velocity_m_s - truth.velocity_m_s);
        t.cpu_us.push_back(cpu);
      }
    }
  }
  nlohmann::json results;
  for (const Method& m : ms) {
    for (double d : distances) {
      results[m.name][std::to_string(static_cast<int>(d))] =
          summarise(tallies[m.name][static_cast<int>(d)]);
    }
    results[m.name]["family"] = m.family;
  }
  print_table(results, ms, distances, trials);
  std::printf(
      "\nPaper, Table 3 (Sphere Fitting) / Table 4 (Scan Line Extent), 200 MHz Pentium Pro, s "
      "min-max:\n");
  for (int i = 0; i < 6; ++i) {
    std::printf("  %4.0f m: %.2f-%.2f   %.4f-%.4f\n", paper::kDistancesM[i], paper::kTable3MinS[i],
                paper::kTable3MaxS[i], paper::kTable4MinS[i], paper::kTable4MaxS[i]);
  }
  std::printf("Paper, Figure 3: %s\nPaper, Figure 4: %s\n", paper::kFigure3, paper::kFigure4);

  out["trials_per_distance"] = trials;
  out["seed"] = seed;
  out["pulse_rate_hz"] = pulse_rate_hz;
  out["methods"] = results;
  for (int i = 0; i < 6; ++i) {
    out["paper"]["table3_sphere_fitting_s"].push_back(
        {paper::kTable3MinS[i], paper::kTable3MaxS[i]});
    out["paper"]["table4_scan_line_extent_s"].push_back(
        {paper::kTable4MinS[i], paper::kTable4MaxS[i]});
  }
  out["paper"]["figure3"] = paper::kFigure3;
  out["paper"]["figure4"] = paper::kFigure4;
  out["paper"]["figure5"] = paper::kFigure5;
  out["paper"]["cpu"] = "200 MHz Pentium Pro";
  if (!json_path.empty()) {
    std::ofstream f(json_path);
    if (!f) {
      std::cerr << "ephor-bench-sphere: cannot write '" << json_path << "'\n";
      return 2;
    }
    f << out.dump(1) << "\n";
  }
  return 0;
}
