#pragma once
// RollingStats: the newest N samples of a quantity (e.g. execution time in
// us) with percentiles, max and the max of the newest k (the paper's
// scheduler estimated a task's cost from its last three runs).

#include <cstddef>
#include <vector>

namespace ephor {

class RollingStats {
 public:
  explicit RollingStats(size_t capacity);

  void add(double sample);
  size_t size() const { return count_; }
  size_t capacity() const { return buf_.size(); }
  bool empty() const { return count_ == 0; }

  // Nearest-rank percentile over the kept samples, p in [0, 100]; 0 if empty.
  double percentile(double p) const;
  double max() const;
  // Max of the newest `k` samples (fewer if fewer kept); 0 if empty.
  double max_of_newest(size_t k) const;
  void clear();

 private:
  std::vector<double> buf_;
  size_t head_ = 0;  // where the next sample goes
  size_t count_ = 0;
};

}  // namespace ephor
