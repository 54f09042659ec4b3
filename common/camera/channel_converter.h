#pragma once
// ChannelConverter: a decoded camera image (OpenCV: 8 or 16 bit; grey, BGR or
// BGRA) -> the one 8-bit channel the vision process works on
// (camera_frame_t: one byte per pixel, row-major, row 0 at the top). The
// shepherding paper digitised only the green channel of its colour camera
// (seed 003, section 2.3), hence the default. kGrey is the luminance
// (OpenCV's BGR2GRAY weights).
//
// Not thread-safe (keeps a scratch image); one per camera.

#include <cstdint>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace ephor::camera {

enum class ColourChannel { kGreen, kRed, kBlue, kGrey };

// "green" / "red" / "blue" / "grey"; parse_colour_channel throws
// std::invalid_argument naming the text otherwise.
const char* colour_channel_name(ColourChannel channel);
ColourChannel parse_colour_channel(const std::string& text);

class ChannelConverter {
 public:
  explicit ChannelConverter(ColourChannel channel = ColourChannel::kGreen) : channel_(channel) {}

  // Writes image's `channel` into `out` (width * height bytes, resized).
  // A one-channel image is taken as it is (there is no colour to pick).
  // 16-bit images are scaled to 8 bits (value / 257). Throws
  // std::invalid_argument naming the problem for an empty image or an
  // unsupported type (2 channels, float pixels, ...).
  void convert(const cv::Mat& image, std::vector<uint8_t>& out);

  ColourChannel channel() const { return channel_; }

 private:
  ColourChannel channel_;
  cv::Mat scratch_;
};

}  // namespace ephor::camera
