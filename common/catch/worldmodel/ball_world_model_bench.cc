// ephor-bench-catch-worldmodel: the time of one BallWorldModel::update (ray,
// gate, Kalman filter, exit and catch prediction) on a ball rolling down the
// default board at 60 Hz, with and without lens distortion (which adds three
// cv::undistortPoints calls per frame: the centroid and the two pixel
// neighbours of the measurement Jacobian). BM_ExitSpread: one ExitSpread
// (32 sampled states and peg sets rolled past 16 pegs) from the top of the
// board, the most rolling there is; BM_WorldModelUpdateWithSpread: the
// update with it on every frame, pegs known.

#include <random>
#include <vector>

#include <benchmark/benchmark.h>

#include "common/catch/worldmodel/ball_world_model.h"
#include "common/catch/worldmodel/exit_spread.h"
#include "common/catch/worldmodel/test_scene.h"

namespace {

using namespace ephor::catching;

// 16 pegs on a 4 x 4 grid between y = 150 and 700 mm, staggered.
std::vector<Eigen::Vector2d> grid_pegs(const BoardSpec& board) {
  std::vector<Eigen::Vector2d> pegs;
  for (int row = 0; row < 4; ++row)
    for (int col = 0; col < 4; ++col)
      pegs.emplace_back(board.width_mm * (0.15 + 0.2 * col + 0.1 * (row % 2)), 150.0 + 180.0 * row);
  return pegs;
}

void run(benchmark::State& state, bool distortion, int spread_samples = 0) {
  const BoardSpec board;
  const BoardPlacement placement;
  CameraIntrinsics intrinsics;
  if (distortion) intrinsics.distortion = {-0.25, 0.08, 0.001, -0.0005, 0.0};
  const Pose b2c = testing::camera_looking_at_board(board);
  const BoardRay ray(board, placement, intrinsics, b2c);
  const auto track = testing::simulate_roll(board, testing::rolling_acceleration(placement),
                                            {220.0, 30.0}, {120.0, 0.0}, 1.0 / 60.0, 0.0, 1);
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.3);
  std::vector<Eigen::Vector2d> pixels;
  for (const auto& s : track) {
    pixels.push_back(*ray.project(Eigen::Vector3d(s.position_mm.x(), s.position_mm.y(),
                                                  board.ball_radius_mm())) +
                     Eigen::Vector2d(noise(rng), noise(rng)));
  }
  BallWorldModelParams params;
  params.spread.samples = spread_samples;
  BallWorldModel wm(board, placement, intrinsics, b2c, params);
  if (spread_samples > 0) wm.set_pegs(grid_pegs(board), 6.0);
  int64_t t = 0;
  std::size_t k = 0;
  for (auto _ : state) {
    if (k == pixels.size()) {
      // A new ball: let the old one time out without timing that frame.
      state.PauseTiming();
      wm.reset();
      k = 0;
      state.ResumeTiming();
    }
    t += 16667;
    benchmark::DoNotOptimize(wm.update(t, pixels[k++]));
  }
  state.counters["frames_per_ball"] = static_cast<double>(pixels.size());
}

void BM_WorldModelUpdate(benchmark::State& state) { run(state, false); }
void BM_WorldModelUpdateDistorted(benchmark::State& state) { run(state, true); }

void BM_WorldModelUpdateWithSpread(benchmark::State& state) { run(state, false, 32); }

void BM_ExitSpread(benchmark::State& state) {
  const BoardSpec board;
  const BoardPlacement placement;
  ExitPredictor predictor(board, placement);
  predictor.set_pegs(grid_pegs(board), 6.0);
  const ExitSpread spread(predictor, {static_cast<int>(state.range(0)), 0.5, 30.0, 1});
  const Eigen::Vector4d s(220.0, 60.0, 40.0, 200.0);
  Eigen::Matrix4d cov = Eigen::Matrix4d::Zero();
  cov.diagonal() << 1.0, 1.0, 100.0, 100.0;
  for (auto _ : state) benchmark::DoNotOptimize(spread.sample(s, cov));
}

BENCHMARK(BM_WorldModelUpdate);
BENCHMARK(BM_WorldModelUpdateDistorted);
BENCHMARK(BM_WorldModelUpdateWithSpread);
BENCHMARK(BM_ExitSpread)->Arg(16)->Arg(32)->Arg(64);

}  // namespace

BENCHMARK_MAIN();
