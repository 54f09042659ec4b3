// Fuzz target (issue 18): the catch vision's board finding on any image, as
// ephor-catch-vision runs it at start-up: CircleFinder::find() over a few
// frames of one size (here up to 160 x 120 px, pixels from the input; the
// camera's intrinsics scaled to that size), with or without the operator's
// windows of interest (--windows, parsed by parse_circle_windows(); a text
// the process would refuse at start is skipped here), then, when the circles
// are found, BoardPoseEstimator::estimate() on their centroids as main.cc
// does. A failure must say why; found circles must be finite.
//
// Input: width and height bytes, a flags byte (bit 0: windows text follows,
// a length byte and the text; bits 1-2: 1 to 3 frames), then the first
// frame's pixels, then for each further frame a count byte of pixels that
// change and (index, value) pairs (frames of a still scene differ a little).
// Seeds: fuzz_corpus/catch_circle_finder (the board rendered at 160 x 120
// face on and tilted, with noise; with windows; a blank frame).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "common/catch/board_model.h"
#include "common/catch/vision/board_pose_estimator.h"
#include "common/catch/vision/circle_finder.h"
#include "common/fuzz/fuzz_input.h"

namespace {

using namespace ephor::catching;

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  ephor::fuzz::FuzzBytes in(data, size);
  const int width = static_cast<int>(in.take_in(1, 160));
  const int height = static_cast<int>(in.take_in(1, 120));
  const uint8_t flags = in.take<uint8_t>();
  CircleFinderOptions options;
  if ((flags & 1) != 0) {
    try {
      options.windows = parse_circle_windows(in.take_string(64));
    } catch (const std::invalid_argument& e) {
      if (std::string(e.what()).empty()) ephor::fuzz::fail("windows refused without a reason");
      return 0;  // the process exits at start with the message
    }
  }
  const int frames_wanted = 1 + ((flags >> 1) & 3) % 3;

  // The default camera (640 x 480, f = 600 px) scaled to the frame.
  CameraIntrinsics camera;
  const double scale = static_cast<double>(width) / 640.0;
  camera.width = width;
  camera.height = height;
  camera.fx = camera.fy = 600.0 * scale;
  camera.cx = (width - 1) / 2.0;
  camera.cy = (height - 1) / 2.0;
  const BoardSpec board;

  std::vector<cv::Mat> frames;
  cv::Mat frame(height, width, CV_8UC1);
  for (int r = 0; r < height; ++r)
    for (int c = 0; c < width; ++c) frame.at<uint8_t>(r, c) = in.take<uint8_t>();
  frames.push_back(frame.clone());
  for (int k = 1; k < frames_wanted; ++k) {
    for (int n = in.take<uint8_t>(); n > 0; --n) {
      const auto at = static_cast<int>(in.take_in(0, width * height - 1));
      frame.at<uint8_t>(at / width, at % width) = in.take<uint8_t>();
    }
    frames.push_back(frame.clone());
  }

  const CircleFinder finder(board, camera, options);
  const CircleFinderResult circles = finder.find(frames);
  if (!circles.found) {
    if (circles.problem.empty()) ephor::fuzz::fail("circles not found and no problem named");
    return 0;
  }
  std::array<Eigen::Vector2d, 4> c;
  for (size_t k = 0; k < 4; ++k) {
    c[k] = circles.circles[k].centroid_px;
    if (!c[k].allFinite()) ephor::fuzz::fail("a circle found at a non-finite centroid");
  }
  const BoardPoseEstimator estimator(board, camera);
  const BoardPoseResult pose = estimator.estimate(c);
  if (!pose.ok && pose.problem.empty()) ephor::fuzz::fail("no board pose and no problem named");
  if (pose.ok && !pose.board_to_camera.matrix().allFinite())
    ephor::fuzz::fail("a board pose that is not finite");
  return 0;
}
