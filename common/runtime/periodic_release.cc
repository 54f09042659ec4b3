#include "common/runtime/periodic_release.h"

#include <stdexcept>

namespace ephor {

PeriodicRelease::PeriodicRelease(int64_t first_release_ns, int64_t period_ns)
    : next_ns_(first_release_ns), period_ns_(period_ns) {
  if (period_ns <= 0) throw std::invalid_argument("PeriodicRelease: period must be > 0 ns");
}

int PeriodicRelease::advance(int64_t now_ns) {
  next_ns_ += period_ns_;
  if (now_ns < next_ns_ + period_ns_) return 0;
  // At least one whole period after the next release has passed: skip to the
  // newest release that is not in the future.
  const int64_t behind = (now_ns - next_ns_) / period_ns_;
  next_ns_ += behind * period_ns_;
  return static_cast<int>(behind);
}

void PeriodicRelease::align(int64_t anchor_ns, int64_t now_ns) {
  // First anchor + k * period strictly after now (floor division for k).
  int64_t k = (now_ns - anchor_ns) / period_ns_;
  if (anchor_ns + k * period_ns_ > now_ns) --k;
  while (anchor_ns + k * period_ns_ <= now_ns) ++k;
  next_ns_ = anchor_ns + k * period_ns_;
}

void PeriodicRelease::set_period(int64_t period_ns) {
  if (period_ns <= 0) throw std::invalid_argument("PeriodicRelease: period must be > 0 ns");
  period_ns_ = period_ns;
}

}  // namespace ephor
