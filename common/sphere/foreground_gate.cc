#include "common/sphere/foreground_gate.h"

#include <algorithm>
#include <vector>

namespace ephor::sphere {

int ForegroundGate::learn(const Window& window) {
  std::vector<double> ranges;
  for (const ScanLine& line : window.lines) {
    for (const Pulse& p : line.pulses) {
      if (p.has_range() && p.range_m < config_.background_range_m) ranges.push_back(p.range_m);
    }
  }
  if (ranges.empty()) {
    median_range_m_ = 0.0;
    return 0;
  }
  const auto mid = ranges.begin() + static_cast<std::ptrdiff_t>(ranges.size() / 2);
  std::nth_element(ranges.begin(), mid, ranges.end());
  median_range_m_ = *mid;
  return static_cast<int>(ranges.size());
}

}  // namespace ephor::sphere
