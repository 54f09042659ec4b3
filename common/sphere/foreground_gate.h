#pragma once
// Which pulses hit the sphere (paper 002, section 2: "the foreground
// measurements on the OS are easily distinguishable from the distant
// background measurements by thresholding"). Two tests: a fixed threshold
// (the far background returns at >= 50 m), then a depth gate around the
// median foreground range, which also drops stray near returns.

#include "common/sphere/scan_types.h"

namespace ephor::sphere {

struct ForegroundGateConfig {
  double background_range_m = 50.0;  // returns at or beyond this are background
  double depth_gate_m = 1.0;         // and within this of the median foreground range
};

class ForegroundGate {
 public:
  ForegroundGate() = default;
  explicit ForegroundGate(const ForegroundGateConfig& config) : config_(config) {}

  // Sets the depth gate's centre from the window's returns. Returns the
  // number of returns closer than the background threshold (estimated from
  // a sample of the pulses; 0 only when there is none).
  int learn(const Window& window);

  bool is_foreground(const Pulse& p) const {
    // A miss (NaN) fails both comparisons. `&`, not `&&`: no branch.
    return static_cast<bool>(
        static_cast<int>(p.range_m < config_.background_range_m) &
        static_cast<int>(std::abs(p.range_m - median_range_m_) <= config_.depth_gate_m));
  }

  double median_range_m() const { return median_range_m_; }

 private:
  ForegroundGateConfig config_;
  double median_range_m_ = 0.0;
};

}  // namespace ephor::sphere
