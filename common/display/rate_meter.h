#pragma once
// RateMeter: messages per second per channel from running totals (e.g. the
// Bus's per-channel received counters), over a sliding window so the figure
// is steady but follows changes within a couple of seconds.
//
// Not thread-safe: one caller at a time.

#include <cstdint>
#include <deque>
#include <map>
#include <string>

namespace ephor::display {

class RateMeter {
 public:
  // window_s: the rate is (newest total - total window_s ago) / elapsed.
  explicit RateMeter(double window_s = 2.0);

  // Adds a sample of running totals (messages since start) at now_s (any
  // monotonic clock, s). Totals that go down (a restart) start over.
  void add_sample(double now_s, const std::map<std::string, uint64_t>& totals);

  // Messages per second per channel (0 for a channel with one sample).
  std::map<std::string, double> rates() const;

 private:
  struct Sample {
    double t_s;
    std::map<std::string, uint64_t> totals;
  };
  double window_s_;
  std::deque<Sample> samples_;
};

}  // namespace ephor::display
