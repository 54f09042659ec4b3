#include "common/shepherd/vision/synthetic_image.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ephor::vision {

SyntheticImage::SyntheticImage(int width, int height, float background)
    : width_(width), height_(height) {
  if (width < 1 || height < 1) throw std::invalid_argument("synthetic image size must be >= 1 px");
  const size_t n = static_cast<size_t>(width) * static_cast<size_t>(height);
  level_.assign(n, background);
  pixels_.assign(n, 0);
}

void SyntheticImage::fill(float level) { std::fill(level_.begin(), level_.end(), level); }

void SyntheticImage::set(int u, int v, float level) {
  if (u < 0 || v < 0 || u >= width_ || v >= height_) return;
  level_[static_cast<size_t>(v) * static_cast<size_t>(width_) + static_cast<size_t>(u)] = level;
}

void SyntheticImage::add_rect(int u0, int v0, int u1, int v1, float level) {
  for (int v = std::max(v0, 0); v <= std::min(v1, height_ - 1); ++v) {
    for (int u = std::max(u0, 0); u <= std::min(u1, width_ - 1); ++u) set(u, v, level);
  }
}

void SyntheticImage::add_disc(double cu, double cv, double radius, float level) {
  constexpr int kSub = 16;
  const double half_diag = std::sqrt(0.5);  // pixel centre to corner, px
  const int u0 = std::max(0, static_cast<int>(std::floor(cu - radius - 1.0)));
  const int u1 = std::min(width_ - 1, static_cast<int>(std::ceil(cu + radius + 1.0)));
  const int v0 = std::max(0, static_cast<int>(std::floor(cv - radius - 1.0)));
  const int v1 = std::min(height_ - 1, static_cast<int>(std::ceil(cv + radius + 1.0)));
  for (int v = v0; v <= v1; ++v) {
    for (int u = u0; u <= u1; ++u) {
      const double d = std::hypot(u - cu, v - cv);
      double cover = 0.0;
      if (d <= radius - half_diag) {
        cover = 1.0;
      } else if (d < radius + half_diag) {
        int inside = 0;
        for (int i = 0; i < kSub; ++i) {
          for (int j = 0; j < kSub; ++j) {
            const double su = u - 0.5 + (j + 0.5) / kSub - cu;
            const double sv = v - 0.5 + (i + 0.5) / kSub - cv;
            if (su * su + sv * sv <= radius * radius) ++inside;
          }
        }
        cover = static_cast<double>(inside) / (kSub * kSub);
      }
      if (cover > 0.0) {
        float& p =
            level_[static_cast<size_t>(v) * static_cast<size_t>(width_) + static_cast<size_t>(u)];
        p += static_cast<float>(cover) * (level - p);
      }
    }
  }
}

ImageView SyntheticImage::render(double noise_sigma, std::mt19937& rng) {
  std::normal_distribution<float> noise(0.0f, static_cast<float>(noise_sigma));
  for (size_t i = 0; i < level_.size(); ++i) {
    float x = level_[i];
    if (noise_sigma > 0.0) x += noise(rng);
    pixels_[i] = static_cast<uint8_t>(std::clamp(std::lround(x), 0L, 255L));
  }
  return ImageView{pixels_.data(), width_, height_, width_};
}

}  // namespace ephor::vision
