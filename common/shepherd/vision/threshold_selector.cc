#include "common/shepherd/vision/threshold_selector.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ephor::vision {

ThresholdSelector::ThresholdSelector(ThresholdSelectorConfig config) : config_(config) {
  if (!(config_.fraction > 0.0 && config_.fraction < 1.0)) {
    throw std::invalid_argument("threshold fraction must be in (0, 1), got " +
                                std::to_string(config_.fraction));
  }
  if (config_.smooth_radius < 0 || config_.smooth_radius > 16) {
    throw std::invalid_argument("threshold smooth_radius must be in 0..16, got " +
                                std::to_string(config_.smooth_radius));
  }
  if (!(config_.tail_fraction > 0.0 && config_.tail_fraction < 1.0)) {
    throw std::invalid_argument("threshold tail_fraction must be in (0, 1), got " +
                                std::to_string(config_.tail_fraction));
  }
  if (config_.min_object_pixels < 1) {
    throw std::invalid_argument("threshold min_object_pixels must be >= 1, got " +
                                std::to_string(config_.min_object_pixels));
  }
  if (!(config_.min_prominence >= 1.0)) {
    throw std::invalid_argument("threshold min_prominence must be >= 1, got " +
                                std::to_string(config_.min_prominence));
  }
}

Histogram ThresholdSelector::histogram(const ImageView& image) {
  Histogram h{};
  // Four partial histograms break the store-to-load dependency on runs of
  // equal pixels (a dark field is mostly one or two grey levels).
  std::array<Histogram, 4> part{};
  for (int v = 0; v < image.height; ++v) {
    const uint8_t* row = image.data + static_cast<std::ptrdiff_t>(v) * image.stride;
    int u = 0;
    for (; u + 4 <= image.width; u += 4) {
      ++part[0][row[u]];
      ++part[1][row[u + 1]];
      ++part[2][row[u + 2]];
      ++part[3][row[u + 3]];
    }
    for (; u < image.width; ++u) ++part[0][row[u]];
  }
  for (int g = 0; g < 256; ++g) {
    const auto i = static_cast<size_t>(g);
    h[i] = part[0][i] + part[1][i] + part[2][i] + part[3][i];
  }
  return h;
}

ThresholdChoice ThresholdSelector::select(const Histogram& hist) const {
  ThresholdChoice out;
  const int r = config_.smooth_radius;
  // Box-filtered counts (sum over the window, not the mean: integer pixels).
  std::array<double, 256> s{};
  uint64_t total = 0;
  for (int g = 0; g < 256; ++g) {
    total += hist[static_cast<size_t>(g)];
    double sum = 0.0;
    for (int d = -r; d <= r; ++d) {
      const int j = g + d;
      if (j >= 0 && j < 256) sum += static_cast<double>(hist[static_cast<size_t>(j)]);
    }
    s[static_cast<size_t>(g)] = sum;
  }
  if (total == 0) {
    out.status = ThresholdStatus::kEmptyHistogram;
    out.message = "histogram is empty (no pixels)";
    return out;
  }
  auto at = [&s](int g) { return s[static_cast<size_t>(g)]; };

  // The field covers most of the image: its peak is the global maximum.
  int bg = 0;
  for (int g = 1; g < 256; ++g) {
    if (at(g) > at(bg)) bg = g;
  }
  out.background_peak = bg;

  // Walk down the background lobe toward the bright end.
  const double tail_level = config_.tail_fraction * at(bg);
  int tail = -1;
  for (int g = bg + 1; g < 256; ++g) {
    if (at(g) < tail_level) {
      tail = g;
      break;
    }
  }
  auto provisional = [&](int from) {
    const int t = (from + 255) / 2;
    return std::clamp(t, 1, 254);
  };
  if (tail < 0) {
    out.status = ThresholdStatus::kNoObjectPeak;
    out.threshold = provisional(bg);
    out.message = "no object peak: the background lobe (peak at grey level " + std::to_string(bg) +
                  ") reaches the bright end of the histogram";
    return out;
  }
  // Then on to the bottom of the valley, so the lobe's last counts are not
  // taken for the object peak.
  while (tail < 255 && at(tail + 1) < at(tail)) ++tail;
  out.background_tail = tail;

  int obj = tail;
  double mean_above = 0.0;
  for (int g = tail; g < 256; ++g) {
    if (at(g) > at(obj)) obj = g;
    mean_above += at(g);
  }
  mean_above /= static_cast<double>(256 - tail);
  const double mass = at(obj);  // raw pixels within +-r of the peak
  if (mass < static_cast<double>(config_.min_object_pixels) ||
      mass < config_.min_prominence * mean_above || obj <= tail) {
    out.status = ThresholdStatus::kNoObjectPeak;
    out.threshold = provisional(tail);
    out.message = "no object peak above the background tail at grey level " + std::to_string(tail) +
                  " (largest: " + std::to_string(static_cast<int>(mass)) + " px at level " +
                  std::to_string(obj) + ", need " + std::to_string(config_.min_object_pixels) +
                  " px standing " + std::to_string(config_.min_prominence) + " x above the tail)";
    return out;
  }
  // A narrow peak gives a plateau of equal smoothed counts: take its middle,
  // then the centre of mass of the raw counts around it.
  int last = obj;
  while (last < 255 && at(last + 1) == at(obj)) ++last;
  const int mid = (obj + last) / 2;
  double w = 0.0, wg = 0.0;
  for (int g = std::max(0, mid - r); g <= std::min(255, mid + r); ++g) {
    w += hist[static_cast<size_t>(g)];
    wg += static_cast<double>(hist[static_cast<size_t>(g)]) * g;
  }
  obj = w > 0.0 ? static_cast<int>(std::lround(wg / w)) : mid;
  out.object_peak = obj;
  const double t = bg + config_.fraction * (obj - bg);
  out.threshold = std::clamp(static_cast<int>(std::lround(t)), 1, 254);
  out.status = ThresholdStatus::kOk;
  return out;
}

}  // namespace ephor::vision
