// ephor-bench-sphere-speed: Google Benchmark of the locators on one paper
// trial per distance (section 4's simulation, seed 1), the window built once
// outside the timed loop. The figure behind the "Scan Line Extent <= 50 us
// per trial at 20 m" target, without the bench's noise generation between
// calls (which evicts the window from the cache in `ephor-bench-sphere`).
//
//   ephor-bench-sphere-speed [--benchmark_filter=ScanLineExtent]

#include <benchmark/benchmark.h>

#include "common/sphere/range_simulator.h"
#include "common/sphere/scan_line_extent.h"
#include "common/sphere/sphere_fitter.h"

namespace {

using namespace ephor::sphere;

Window paper_window(double distance_m) {
  RangeSimulator sim(RangeSimulator::paper_trial(distance_m, 1));
  Window w;
  w.t_begin_s = 0.0;
  w.t_end_s = 0.5;
  w.lines = sim.scan(0.0, 0.5);
  return w;
}

void BM_ScanLineExtent(benchmark::State& state, bool improved) {
  const Window w = paper_window(static_cast<double>(state.range(0)));
  const ScanLineExtent sle(improved ? ScanLineExtentConfig::improved()
                                    : ScanLineExtentConfig::paper());
  for (auto _ : state) {
    Estimate e = sle.locate(w);
    benchmark::DoNotOptimize(e);
  }
}

void BM_SphereFitter(benchmark::State& state, bool improved) {
  const Window w = paper_window(static_cast<double>(state.range(0)));
  const SphereFitter fit(improved ? SphereFitterConfig::improved() : SphereFitterConfig::paper());
  for (auto _ : state) {
    Estimate e = fit.locate(w);
    benchmark::DoNotOptimize(e);
  }
}

}  // namespace

BENCHMARK_CAPTURE(BM_ScanLineExtent, paper, false)
    ->Arg(1)
    ->Arg(5)
    ->Arg(20)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_ScanLineExtent, improved, true)
    ->Arg(1)
    ->Arg(5)
    ->Arg(20)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_SphereFitter, improved, true)->Arg(1)->Arg(20)->Unit(benchmark::kMicrosecond);

namespace {

// The floor under Scan Line Extent: learning the gate, the pulse step and
// the slopes, and gating every pulse, with every line then refused.
void BM_ScanLineExtentGatingOnly(benchmark::State& state) {
  const Window w = paper_window(static_cast<double>(state.range(0)));
  ScanLineExtentConfig c = ScanLineExtentConfig::improved();
  c.min_points_per_line = 100000;
  const ScanLineExtent sle(c);
  for (auto _ : state) {
    Estimate e = sle.locate(w);
    benchmark::DoNotOptimize(e);
  }
}

}  // namespace

BENCHMARK(BM_ScanLineExtentGatingOnly)->Arg(20)->Unit(benchmark::kMicrosecond);

BENCHMARK_MAIN();
