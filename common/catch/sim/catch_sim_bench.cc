// ephor-bench-catch-sim: how fast the catching world runs.
//
//   ephor-bench-catch-sim [Google Benchmark flags]
//
//   BM_RenderFrame           one 640 x 480 frame: background copy, ball, noise
//   BM_RenderFrameWithArm    the same with a five-link arm and the cup in view
//   BM_RenderBackground      the static scene, once per scenario
//   BM_PhysicsStep           one 1 ms Box2D step of the ball among the pegs
//   BM_PredictExit           predict_exit() from the release (a whole descent)

#include <benchmark/benchmark.h>

#include "common/catch/sim/board_renderer.h"
#include "common/catch/sim/board_world.h"

namespace {

using namespace ephor::catching;

ArmView bench_arm(const CatchScenario& s) {
  // A PUMA-sized arm beside the bottom edge, holding the cup at the catch plane.
  const Eigen::Vector3d tip = s.placement.bottom_centre_w_mm + Eigen::Vector3d(-120.0, 0.0, -80.0);
  ArmView arm;
  arm.links_w = {{Eigen::Vector3d(0, -300, 0), Eigen::Vector3d(0, -300, 660), 80.0},
                 {Eigen::Vector3d(0, -300, 660), Eigen::Vector3d(0, -100, 660), 70.0},
                 {Eigen::Vector3d(0, -100, 660), Eigen::Vector3d(350, -100, 600), 55.0},
                 {Eigen::Vector3d(350, -100, 600), tip + Eigen::Vector3d(0, -60, 150), 45.0},
                 {tip + Eigen::Vector3d(0, -60, 150), tip + Eigen::Vector3d(0, -60, 0), 30.0}};
  arm.cup_opening_w_mm = tip;
  return arm;
}

void BM_RenderFrame(benchmark::State& state) {
  const CatchScenario s = CatchScenario::draw(1);
  BoardRenderer renderer(s);
  cv::Mat image;
  double y = 100.0;
  for (auto _ : state) {
    y = y > 850.0 ? 100.0 : y + 10.0;
    auto uv = renderer.render(Eigen::Vector3d(300.0, y, 20.0), {}, image);
    benchmark::DoNotOptimize(uv);
    benchmark::DoNotOptimize(image.data);
  }
}
BENCHMARK(BM_RenderFrame)->Unit(benchmark::kMillisecond);

void BM_RenderFrameWithArm(benchmark::State& state) {
  const CatchScenario s = CatchScenario::draw(1);
  BoardRenderer renderer(s);
  const ArmView arm = bench_arm(s);
  cv::Mat image;
  double y = 100.0;
  for (auto _ : state) {
    y = y > 850.0 ? 100.0 : y + 10.0;
    auto uv = renderer.render(Eigen::Vector3d(300.0, y, 20.0), arm, image);
    benchmark::DoNotOptimize(uv);
    benchmark::DoNotOptimize(image.data);
  }
}
BENCHMARK(BM_RenderFrameWithArm)->Unit(benchmark::kMillisecond);

void BM_RenderBackground(benchmark::State& state) {
  const CatchScenario s = CatchScenario::draw(1);
  for (auto _ : state) {
    BoardRenderer renderer(s);
    benchmark::DoNotOptimize(renderer.background().data);
  }
}
BENCHMARK(BM_RenderBackground)->Unit(benchmark::kMillisecond);

void BM_PhysicsStep(benchmark::State& state) {
  const CatchScenario s = CatchScenario::draw(1);
  BoardWorld world(s);
  int k = 0;
  world.release(s.release(k));
  for (auto _ : state) {
    world.step(0.001);
    if (world.exit() || world.stalled()) {
      state.PauseTiming();
      world.release(s.release(++k));
      state.ResumeTiming();
    }
  }
}
BENCHMARK(BM_PhysicsStep)->Unit(benchmark::kMicrosecond);

void BM_PredictExit(benchmark::State& state) {
  const CatchScenario s = CatchScenario::draw(1);
  BoardWorld world(s);
  world.release(s.release(0));
  for (auto _ : state) {
    auto p = world.predict_exit();
    benchmark::DoNotOptimize(p);
  }
}
BENCHMARK(BM_PredictExit)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
