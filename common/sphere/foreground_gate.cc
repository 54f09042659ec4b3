#include "common/sphere/foreground_gate.h"

#include <algorithm>
#include <vector>

namespace ephor::sphere {

int ForegroundGate::learn(const Window& window) {
  // The median of at most ~256 near returns spread over the window: plenty
  // for a gate a metre wide, and it keeps the locator's cost linear.
  thread_local std::vector<double> all, ranges;
  all.clear();
  ranges.clear();
  for (const ScanLine& line : window.lines) {
    for (const Pulse& p : line.pulses) {
      // NaN compares false: misses drop out here.
      if (p.range_m < config_.background_range_m) all.push_back(p.range_m);
    }
  }
  const int near = static_cast<int>(all.size());
  const size_t stride = std::max<size_t>(1, all.size() / 256);
  for (size_t k = 0; k < all.size(); k += stride) ranges.push_back(all[k]);
  if (ranges.empty()) {
    median_range_m_ = 0.0;
    return 0;
  }
  const auto mid = ranges.begin() + static_cast<std::ptrdiff_t>(ranges.size() / 2);
  std::nth_element(ranges.begin(), mid, ranges.end());
  median_range_m_ = *mid;
  return near;
}

}  // namespace ephor::sphere
