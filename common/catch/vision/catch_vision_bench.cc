// Timing of the catch vision (paper 000): frame differencing full-frame and
// windowed, the MOG2 peer, the circle finder, and IPPE vs iterative PnP, on
// synthetic 640 x 480 frames of a board with a rolling ball (noise sigma 2).

#include <vector>

#include <benchmark/benchmark.h>

#include "common/catch/vision/board_pose_estimator.h"
#include "common/catch/vision/circle_finder.h"
#include "common/catch/vision/motion_centroid.h"
#include "common/catch/vision/test_scenes.h"

namespace ephor::catching {
namespace {

const std::vector<cv::Mat>& rolling_frames() {
  static const std::vector<cv::Mat> frames = [] {
    std::vector<cv::Mat> out;
    SyntheticScene s = testing::board_scene(1500.0, 25.0);
    for (int k = 0; k < 16; ++k) {
      s.ball = SyntheticBall{{250.0 + 5.0 * k, 200.0 + 37.5 * k}, 5.0};
      out.push_back(render_board(s, 2.0, 77 + static_cast<uint64_t>(k)));
    }
    return out;
  }();
  return frames;
}

Eigen::Vector2d ball_px(int k) {
  const SyntheticScene s = testing::board_scene(1500.0, 25.0);
  return project_pinhole(s.camera, s.board_to_camera,
                         Eigen::Vector3d(250.0 + 5.0 * k, 200.0 + 37.5 * k, 20.0));
}

void run_detector(benchmark::State& state, MotionDetector& detector, bool windowed) {
  const auto& frames = rolling_frames();
  size_t k = 0;
  double found = 0.0, n = 0.0;
  for (auto _ : state) {
    std::optional<cv::Rect> window;
    if (windowed) {
      const Eigen::Vector2d p = ball_px(static_cast<int>(k % frames.size()));
      window = cv::Rect(static_cast<int>(p.x()) - 40, static_cast<int>(p.y()) - 40, 80, 80);
    }
    const MotionMeasurement m = detector.process(frames[k % frames.size()], window);
    benchmark::DoNotOptimize(m);
    found += m.found ? 1.0 : 0.0;
    n += 1.0;
    ++k;
  }
  state.counters["found_fraction"] = found / n;
}

void BM_MotionCentroidFullFrame(benchmark::State& state) {
  MotionCentroid m;
  run_detector(state, m, false);
}
BENCHMARK(BM_MotionCentroidFullFrame)->Unit(benchmark::kMicrosecond);

void BM_MotionCentroidWindowed80(benchmark::State& state) {
  MotionCentroid m;
  run_detector(state, m, true);
}
BENCHMARK(BM_MotionCentroidWindowed80)->Unit(benchmark::kMicrosecond);

void BM_Mog2FullFrame(benchmark::State& state) {
  Mog2Centroid m;
  run_detector(state, m, false);
}
BENCHMARK(BM_Mog2FullFrame)->Unit(benchmark::kMicrosecond);

void BM_CircleFinderOneFrame(benchmark::State& state) {
  const SyntheticScene s = testing::board_scene(1500.0, 35.0, 20.0, 8.0);
  const cv::Mat frame = render_board(s, 2.0, 5);
  const CircleFinder finder(s.board, s.camera);
  for (auto _ : state) benchmark::DoNotOptimize(finder.find(frame));
}
BENCHMARK(BM_CircleFinderOneFrame)->Unit(benchmark::kMillisecond);

void run_pose(benchmark::State& state, PnpMethod method, int iterations) {
  const SyntheticScene s = testing::board_scene(1500.0, 60.0);
  const BoardPoseEstimator est(s.board, s.camera);
  std::array<Eigen::Vector2d, 4> c;
  for (int i = 0; i < 4; ++i)
    c[static_cast<size_t>(i)] = est.project_circle(s.board_to_camera, i).centroid_px;
  for (auto _ : state) benchmark::DoNotOptimize(est.estimate(c, {method, iterations}));
}
void BM_PoseIppe(benchmark::State& state) { run_pose(state, PnpMethod::kIppe, 0); }
void BM_PoseIppeBiasCorrected(benchmark::State& state) { run_pose(state, PnpMethod::kIppe, 3); }
void BM_PoseIterative(benchmark::State& state) { run_pose(state, PnpMethod::kIterative, 0); }
void BM_PoseIterativeBiasCorrected(benchmark::State& state) {
  run_pose(state, PnpMethod::kIterative, 3);
}
BENCHMARK(BM_PoseIppe)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_PoseIppeBiasCorrected)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_PoseIterative)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_PoseIterativeBiasCorrected)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace ephor::catching

BENCHMARK_MAIN();
