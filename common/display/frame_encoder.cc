#include "common/display/frame_encoder.h"

#include <stdexcept>
#include <string>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

namespace ephor::display {

FrameEncoder::FrameEncoder(int quality) : quality_(quality) {
  if (quality < 1 || quality > 100) {
    throw std::invalid_argument("JPEG quality " + std::to_string(quality) + " is not in 1..100");
  }
}

const std::vector<uint8_t>& FrameEncoder::encode(const uint8_t* pixels, int64_t size_bytes,
                                                 int width_px, int height_px) {
  if (width_px < 1 || height_px < 1 || width_px > 8192 || height_px > 8192) {
    throw std::invalid_argument("frame size " + std::to_string(width_px) + " x " +
                                std::to_string(height_px) + " px is not 1..8192 per side");
  }
  if (pixels == nullptr || size_bytes != static_cast<int64_t>(width_px) * height_px) {
    throw std::invalid_argument("frame carries " + std::to_string(size_bytes) +
                                " bytes, want width * height = " +
                                std::to_string(static_cast<int64_t>(width_px) * height_px));
  }
  // OpenCV only reads through this header; the const_cast does not write.
  const cv::Mat image(height_px, width_px, CV_8UC1, const_cast<uint8_t*>(pixels));
  if (!cv::imencode(".jpg", image, jpeg_, {cv::IMWRITE_JPEG_QUALITY, quality_})) {
    throw std::runtime_error("OpenCV could not encode the frame as JPEG");
  }
  return jpeg_;
}

}  // namespace ephor::display
