#include "common/shepherd/vision/foreground_image.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ephor::vision {

const char* foreground_mode_name(ForegroundMode mode) {
  switch (mode) {
    case ForegroundMode::kBright:
      return "bright";
    case ForegroundMode::kDark:
      return "dark";
    case ForegroundMode::kMotion:
      return "motion";
  }
  return "?";
}

ForegroundMode parse_foreground_mode(const std::string& text) {
  if (text == "bright") return ForegroundMode::kBright;
  if (text == "dark") return ForegroundMode::kDark;
  if (text == "motion") return ForegroundMode::kMotion;
  throw std::invalid_argument("foreground mode '" + text + "' is not bright, dark or motion");
}

ForegroundImage::ForegroundImage(ForegroundConfig config) : config_(config) {
  if (!(config_.background_rate > 0.0 && config_.background_rate <= 1.0)) {
    throw std::invalid_argument("foreground background_rate " +
                                std::to_string(config_.background_rate) + " is outside (0, 1]");
  }
  if (config_.smooth_radius_px < 0 || config_.smooth_radius_px > 64) {
    throw std::invalid_argument("foreground smooth_radius_px " +
                                std::to_string(config_.smooth_radius_px) + " is outside 0..64");
  }
  if (config_.mode != ForegroundMode::kBright && config_.mode != ForegroundMode::kDark &&
      config_.mode != ForegroundMode::kMotion) {
    throw std::invalid_argument("foreground mode " +
                                std::to_string(static_cast<int>(config_.mode)) + " is unknown");
  }
}

ImageView ForegroundImage::apply(const ImageView& frame) {
  if (const std::string problem = check_image(frame); !problem.empty()) {
    throw std::invalid_argument(problem);
  }
  if (config_.mode == ForegroundMode::kBright) return frame;
  if (frame.width != width_ || frame.height != height_) {
    width_ = frame.width;
    height_ = frame.height;
    reference_.clear();
  }
  out_.resize(static_cast<size_t>(width_) * static_cast<size_t>(height_));
  if (config_.mode == ForegroundMode::kDark) {
    for (int v = 0; v < height_; ++v) {
      uint8_t* out = out_.data() + static_cast<ptrdiff_t>(v) * width_;
      for (int u = 0; u < width_; ++u) out[u] = static_cast<uint8_t>(255 - frame.at(u, v));
    }
  } else {
    difference(frame);
    if (config_.smooth_radius_px > 0) smooth(width_, height_);
  }
  return ImageView{out_.data(), width_, height_, width_};
}

void ForegroundImage::difference(const ImageView& frame) {
  const bool first = reference_.empty();
  if (first) reference_.resize(out_.size());
  const float rate = static_cast<float>(config_.background_rate);
  for (int v = 0; v < height_; ++v) {
    const size_t row = static_cast<size_t>(v) * static_cast<size_t>(width_);
    for (int u = 0; u < width_; ++u) {
      const float pixel = frame.at(u, v);
      float& ref = reference_[row + static_cast<size_t>(u)];
      if (first) ref = pixel;
      const float d = std::min(255.0f, std::abs(pixel - ref));
      out_[row + static_cast<size_t>(u)] = static_cast<uint8_t>(std::lround(d));
      ref += rate * (pixel - ref);
    }
  }
}

void ForegroundImage::smooth(int width, int height) {
  // Integral image, then the mean over the clipped box around each pixel.
  const size_t w1 = static_cast<size_t>(width) + 1;
  sums_.assign(w1 * (static_cast<size_t>(height) + 1), 0);
  for (int v = 0; v < height; ++v) {
    uint32_t row_sum = 0;
    for (int u = 0; u < width; ++u) {
      row_sum += out_[static_cast<size_t>(v) * static_cast<size_t>(width) + static_cast<size_t>(u)];
      sums_[(static_cast<size_t>(v) + 1) * w1 + static_cast<size_t>(u) + 1] =
          sums_[static_cast<size_t>(v) * w1 + static_cast<size_t>(u) + 1] + row_sum;
    }
  }
  const int r = config_.smooth_radius_px;
  for (int v = 0; v < height; ++v) {
    const size_t v0 = static_cast<size_t>(std::max(0, v - r));
    const size_t v1 = static_cast<size_t>(std::min(height, v + r + 1));
    for (int u = 0; u < width; ++u) {
      const size_t u0 = static_cast<size_t>(std::max(0, u - r));
      const size_t u1 = static_cast<size_t>(std::min(width, u + r + 1));
      const uint32_t sum =
          sums_[v1 * w1 + u1] - sums_[v0 * w1 + u1] - sums_[v1 * w1 + u0] + sums_[v0 * w1 + u0];
      const auto n = static_cast<uint32_t>((v1 - v0) * (u1 - u0));
      out_[static_cast<size_t>(v) * static_cast<size_t>(width) + static_cast<size_t>(u)] =
          static_cast<uint8_t>((sum + n / 2) / n);
    }
  }
}

}  // namespace ephor::vision
