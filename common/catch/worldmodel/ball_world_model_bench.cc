// ephor-bench-catch-worldmodel: the time of one BallWorldModel::update (ray,
// gate, Kalman filter, exit and catch prediction) on a ball rolling down the
// default board at 60 Hz, with and without lens distortion (which adds three
// cv::undistortPoints calls per frame: the centroid and the two pixel
// neighbours of the measurement Jacobian).

#include <random>
#include <vector>

#include <benchmark/benchmark.h>

#include "common/catch/worldmodel/ball_world_model.h"
#include "common/catch/worldmodel/test_scene.h"

namespace {

using namespace ephor::catching;

void run(benchmark::State& state, bool distortion) {
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
  BallWorldModel wm(board, placement, intrinsics, b2c);
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

BENCHMARK(BM_WorldModelUpdate);
BENCHMARK(BM_WorldModelUpdateDistorted);

}  // namespace

BENCHMARK_MAIN();
