#include "common/camera/channel_converter.h"

#include <stdexcept>

#include <opencv2/imgproc.hpp>

namespace ephor::camera {

const char* colour_channel_name(ColourChannel channel) {
  switch (channel) {
    case ColourChannel::kGreen:
      return "green";
    case ColourChannel::kRed:
      return "red";
    case ColourChannel::kBlue:
      return "blue";
    case ColourChannel::kGrey:
      return "grey";
  }
  return "?";
}

ColourChannel parse_colour_channel(const std::string& text) {
  if (text == "green") return ColourChannel::kGreen;
  if (text == "red") return ColourChannel::kRed;
  if (text == "blue") return ColourChannel::kBlue;
  if (text == "grey" || text == "gray") return ColourChannel::kGrey;
  throw std::invalid_argument("colour channel '" + text + "' is not green, red, blue or grey");
}

void ChannelConverter::convert(const cv::Mat& image, std::vector<uint8_t>& out) {
  if (image.empty()) throw std::invalid_argument("camera image is empty");
  const int depth = image.depth();
  const int channels = image.channels();
  if (depth != CV_8U && depth != CV_16U) {
    throw std::invalid_argument("camera image has pixel depth " + std::to_string(depth) +
                                " (OpenCV type " + std::to_string(image.type()) +
                                "); want 8 or 16 bit unsigned");
  }
  if (channels != 1 && channels != 3 && channels != 4) {
    throw std::invalid_argument("camera image has " + std::to_string(channels) +
                                " channels; want 1 (grey), 3 (BGR) or 4 (BGRA)");
  }
  cv::Mat one;
  if (channels == 1) {
    one = image;
  } else if (channel_ == ColourChannel::kGrey) {
    cv::cvtColor(image, scratch_, channels == 4 ? cv::COLOR_BGRA2GRAY : cv::COLOR_BGR2GRAY);
    one = scratch_;
  } else {
    // OpenCV orders colour as B, G, R(, A).
    const int index =
        channel_ == ColourChannel::kBlue ? 0 : (channel_ == ColourChannel::kGreen ? 1 : 2);
    cv::extractChannel(image, scratch_, index);
    one = scratch_;
  }
  if (depth == CV_16U) {
    cv::Mat eight;
    one.convertTo(eight, CV_8U, 1.0 / 257.0);
    one = eight;
  }
  const auto width = static_cast<size_t>(one.cols);
  out.resize(width * static_cast<size_t>(one.rows));
  for (int r = 0; r < one.rows; ++r) {
    const uint8_t* row = one.ptr<uint8_t>(r);
    std::copy(row, row + width, out.begin() + static_cast<std::ptrdiff_t>(width) * r);
  }
}

}  // namespace ephor::camera
