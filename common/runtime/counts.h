#pragma once
// Counts that arrive on the wire (deadline misses, jobs) are summed over
// tasks and hosts. A corrupt or hostile message can carry any int64: a
// negative count is taken as 0 and the sum saturates at INT64_MAX rather
// than overflowing (undefined behaviour in C++).

#include <cstdint>
#include <limits>

namespace ephor {

inline int64_t add_count(int64_t sum, int64_t n) {
  if (n <= 0) return sum;
  const int64_t max = std::numeric_limits<int64_t>::max();
  return n > max - sum ? max : sum + n;
}

}  // namespace ephor
