#include "common/runtime/rolling_stats.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ephor {

RollingStats::RollingStats(size_t capacity) : buf_(capacity) {
  if (capacity == 0) throw std::invalid_argument("RollingStats: capacity must be > 0");
}

void RollingStats::add(double sample) {
  buf_[head_] = sample;
  head_ = (head_ + 1) % buf_.size();
  count_ = std::min(count_ + 1, buf_.size());
}

double RollingStats::percentile(double p) const {
  if (count_ == 0) return 0.0;
  std::vector<double> v;
  v.reserve(count_);
  for (size_t i = 0; i < count_; ++i)
    v.push_back(buf_[(head_ + buf_.size() - 1 - i) % buf_.size()]);
  p = std::clamp(p, 0.0, 100.0);
  // Nearest rank: the smallest value with at least p% of samples <= it.
  size_t rank = static_cast<size_t>(std::ceil(p / 100.0 * static_cast<double>(count_)));
  rank = std::clamp<size_t>(rank, 1, count_);
  std::nth_element(v.begin(), v.begin() + static_cast<long>(rank - 1), v.end());
  return v[rank - 1];
}

double RollingStats::max() const { return max_of_newest(count_); }

double RollingStats::max_of_newest(size_t k) const {
  k = std::min(k, count_);
  if (k == 0) return 0.0;
  double m = -INFINITY;
  for (size_t i = 0; i < k; ++i) m = std::max(m, buf_[(head_ + buf_.size() - 1 - i) % buf_.size()]);
  return m;
}

void RollingStats::clear() {
  head_ = 0;
  count_ = 0;
}

}  // namespace ephor
