// ephor-bench-sim: how fast the simulator runs (tools/ephor bench sim).
//
//   ephor-bench-sim [--json FILE] [Google Benchmark flags]
//
//   BM_RenderFrame/N     one 512 x 482 frame with N sheep and the arm (target: a few ms)
//   BM_SimulateSecond/N  one simulated second of N sheep and the servo (1 ms servo, 4 ms steps)
//   BM_MarkCentroid      counters: rms and max error (px) of the thresholded and the
//                        intensity-weighted mark centroid against the projected truth,
//                        default noise and lighting (what the vision can reach)

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "common/shepherd/sim/simulator.h"

namespace {

using ephor::sim::Simulator;
using ephor::sim::SimulatorConfig;

void BM_RenderFrame(benchmark::State& state) {
  SimulatorConfig c;
  c.world.sheep = static_cast<int>(state.range(0));
  Simulator sim(c);
  std::vector<uint8_t> img;
  for (auto _ : state) {
    auto gt = sim.render(img);
    benchmark::DoNotOptimize(gt);
    benchmark::DoNotOptimize(img.data());
  }
}
BENCHMARK(BM_RenderFrame)->Arg(4)->Arg(8)->Unit(benchmark::kMillisecond);

void BM_SimulateSecond(benchmark::State& state) {
  SimulatorConfig c;
  c.world.sheep = static_cast<int>(state.range(0));
  Simulator sim(c);
  for (auto _ : state) {
    for (int i = 0; i < 250; ++i) sim.step(0.004);
  }
  state.counters["x_real_time"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_SimulateSecond)->Arg(4)->Arg(8)->Unit(benchmark::kMillisecond);

void BM_MarkCentroid(benchmark::State& state) {
  SimulatorConfig c;
  c.world.sheep = 6;
  Simulator sim(c);
  std::vector<uint8_t> img;
  double sum2_bin = 0, max_bin = 0, sum2_w = 0, max_w = 0;
  int n = 0;
  for (auto _ : state) {
    sim.step(0.5);
    const auto gt = sim.render(img);
    for (const auto& s : gt.sheep) {
      if (!s.view.visible || s.view.hidden_fraction > 0.0) continue;
      const int cu = static_cast<int>(std::lround(s.view.centre_px.x()));
      const int cv = static_cast<int>(std::lround(s.view.centre_px.y()));
      double bn = 0, bu = 0, bv = 0, wn = 0, wu = 0, wv = 0;
      for (int v = cv - 14; v <= cv + 14; ++v) {
        for (int u = cu - 14; u <= cu + 14; ++u) {
          if (u < 0 || v < 0 || u >= 512 || v >= 482) continue;
          const double g = img[static_cast<size_t>(v) * 512 + static_cast<size_t>(u)];
          if (g >= 200.0) bn += 1, bu += u, bv += v;  // the vision's kind of threshold
          const double w = std::max(0.0, g - 100.0);
          wn += w, wu += w * u, wv += w * v;
        }
      }
      const double eb = std::hypot(bu / bn - s.view.centre_px.x(), bv / bn - s.view.centre_px.y());
      const double ew = std::hypot(wu / wn - s.view.centre_px.x(), wv / wn - s.view.centre_px.y());
      sum2_bin += eb * eb, max_bin = std::max(max_bin, eb);
      sum2_w += ew * ew, max_w = std::max(max_w, ew);
      ++n;
    }
  }
  state.counters["marks"] = n;
  state.counters["threshold_rms_px"] = std::sqrt(sum2_bin / std::max(n, 1));
  state.counters["threshold_max_px"] = max_bin;
  state.counters["weighted_rms_px"] = std::sqrt(sum2_w / std::max(n, 1));
  state.counters["weighted_max_px"] = max_w;
}
BENCHMARK(BM_MarkCentroid)->Iterations(200)->Unit(benchmark::kMillisecond);

}  // namespace

int main(int argc, char** argv) {
  // --json FILE -> Google Benchmark's JSON output file.
  std::vector<std::string> args(argv, argv + argc);
  std::vector<std::string> out;
  for (size_t i = 0; i < args.size(); ++i) {
    if (args[i] == "--json" && i + 1 < args.size()) {
      out.push_back("--benchmark_out=" + args[++i]);
      out.push_back("--benchmark_out_format=json");
    } else {
      out.push_back(args[i]);
    }
  }
  std::vector<char*> cargs;
  for (auto& a : out) cargs.push_back(a.data());
  int n = static_cast<int>(cargs.size());
  benchmark::Initialize(&n, cargs.data());
  if (benchmark::ReportUnrecognizedArguments(n, cargs.data())) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
