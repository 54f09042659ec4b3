#pragma once
// FrameEncoder: a monochrome camera frame (camera_frame_t layout: row-major,
// one byte per pixel) as a JPEG for the page. JPEG rather than PNG: about a
// tenth of the bytes and of the encoding time for a noisy 512 x 482 image.
//
// Not thread-safe (keeps its output buffer); one encoder per thread.

#include <cstdint>
#include <vector>

namespace ephor::display {

class FrameEncoder {
 public:
  // quality: JPEG quality 1..100 (throws std::invalid_argument otherwise).
  explicit FrameEncoder(int quality = 75);

  // Encodes width x height bytes at `pixels`. Throws std::invalid_argument
  // when the size is not 1..8192 px per side or `size_bytes` differs from
  // width * height.
  const std::vector<uint8_t>& encode(const uint8_t* pixels, int64_t size_bytes, int width_px,
                                     int height_px);

 private:
  int quality_;
  std::vector<uint8_t> jpeg_;
};

}  // namespace ephor::display
