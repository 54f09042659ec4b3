#include "common/sphere/foreground_gate.h"

#include <algorithm>
#include <vector>

namespace ephor::sphere {

int ForegroundGate::learn(const Window& window) {
  // The median of about 256 near returns spread over the window: plenty for
  // a gate a metre wide. Every k-th pulse is looked at (k from the window's
  // pulse count) so the cost stays well below one pass over the pulses; the
  // count of near returns is extrapolated from the sample, and a full pass
  // is made when the sample holds fewer than 32 (a sphere small in the frame).
  thread_local std::vector<double> ranges;
  size_t pulses = 0;
  for (const ScanLine& line : window.lines) pulses += line.pulses.size();
  const auto sample = [&](size_t stride) {
    ranges.clear();
    size_t k = 0;
    for (const ScanLine& line : window.lines) {
      for (; k < line.pulses.size(); k += stride) {
        // NaN compares false: misses drop out here.
        const double r = line.pulses[k].range_m;
        if (r < config_.background_range_m) ranges.push_back(r);
      }
      k -= line.pulses.size();
    }
  };
  size_t stride = std::max<size_t>(1, pulses / 512);
  sample(stride);
  if (stride > 1 && ranges.size() < 32) {
    stride = 1;
    sample(stride);
  }
  if (ranges.empty()) {
    median_range_m_ = 0.0;
    return 0;
  }
  const int near = static_cast<int>(ranges.size() * stride);
  const auto mid = ranges.begin() + static_cast<std::ptrdiff_t>(ranges.size() / 2);
  std::nth_element(ranges.begin(), mid, ranges.end());
  median_range_m_ = *mid;
  return near;
}

}  // namespace ephor::sphere
