// Fuzz target (issue 18): camera frames as ephor-catch-vision handles them
// once the board is found: a run of up to eight frames of one size (up to
// 64 x 48 px, pixels from the input) through MotionCentroid, each with the
// window of interest the process derives from the world model, which may be
// absent, empty, partly or wholly outside the image; a gap in the frame
// indices resets it, as main.cc does. The found centre must be finite.
// Seeds: fuzz_corpus/catch_motion.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include <opencv2/core.hpp>

#include "common/catch/vision/motion_centroid.h"
#include "common/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  ephor::fuzz::FuzzBytes in(data, size);
  const int width = static_cast<int>(in.take_in(1, 64));
  const int height = static_cast<int>(in.take_in(1, 48));
  ephor::catching::MotionCentroid motion;
  std::vector<uint8_t> pixels(static_cast<size_t>(width) * static_cast<size_t>(height));
  for (int k = 0; k < 8 && !in.empty(); ++k) {
    const uint8_t how = in.take<uint8_t>();
    if ((how & 0x80) != 0) motion.reset();  // a gap in the frame indices
    // A new frame, or the previous one with a few pixels changed (a moving ball).
    if ((how & 0x40) != 0 || k == 0) {
      for (uint8_t& p : pixels) p = in.take<uint8_t>();
    } else {
      for (int n = in.take_in(0, 40); n > 0; --n)
        pixels[static_cast<size_t>(in.take_in(0, width * height - 1))] = in.take<uint8_t>();
    }
    std::optional<cv::Rect> window;
    if ((how & 0x20) != 0)
      window =
          cv::Rect(static_cast<int>(in.take_in(-80, 80)), static_cast<int>(in.take_in(-80, 80)),
                   static_cast<int>(in.take_in(-8, 100)), static_cast<int>(in.take_in(-8, 100)));
    const cv::Mat image(height, width, CV_8UC1, pixels.data());
    const ephor::catching::MotionMeasurement m = motion.process(image, window);
    if (m.found && !(std::isfinite(m.centroid_px.x()) && std::isfinite(m.centroid_px.y())))
      ephor::fuzz::fail("a ball found at a non-finite position");
  }
  return 0;
}
