// Fuzz target (issue 18): camera frames as ephor-rambo-features handles them:
// the frame's size checked as main.cc does, then extract_image_features on
// the grey image (corners, edges, triples), on arbitrary pixels up to
// 96 x 96 px: blank frames, noise, stripes, a single bright pixel.
// Seeds: fuzz_corpus/rambo_features.
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include <opencv2/core.hpp>

#include "common/fuzz/fuzz_input.h"
#include "common/rambo/image_features.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  ephor::fuzz::FuzzBytes in(data, size);
  const int width = static_cast<int>(in.take_in(1, 96));
  const int height = static_cast<int>(in.take_in(1, 96));
  std::vector<uint8_t> pixels(static_cast<size_t>(width) * static_cast<size_t>(height));
  for (uint8_t& p : pixels) p = in.take<uint8_t>();
  const cv::Mat grey(height, width, CV_8UC1, pixels.data());
  const ephor::rambo::ImageFeatures f = ephor::rambo::extract_image_features(grey);
  const int corners = static_cast<int>(f.corners_px.size());
  for (const auto& [i, j] : f.edges)
    if (i < 0 || j < 0 || i >= corners || j >= corners || i >= j)
      ephor::fuzz::fail("an edge joins corners that do not exist");
  return 0;
}
