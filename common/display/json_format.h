#pragma once
// Number formatting shared by the display pages' state builders (the JSON
// of GET /api/state): small, and never NaN (which JSON cannot carry).

#include <cmath>
#include <cstdint>

namespace ephor::display {

// Rounded to 0.1 so the JSON stays small; NaN and infinities become 0.
inline double r1(double x) { return std::isfinite(x) ? std::round(x * 10.0) / 10.0 : 0.0; }

// Rounded to `digits` decimals; NaN and infinities become 0.
inline double rounded(double x, int digits) {
  if (!std::isfinite(x)) return 0.0;
  const double scale = std::pow(10.0, digits);
  return std::round(x * scale) / scale;
}

// Age in ms of something received at `then_us` (wall clock, us), or -1 when never.
inline double age_ms(int64_t then_us, int64_t now_us) {
  return then_us == 0 ? -1.0 : static_cast<double>(now_us - then_us) / 1e3;
}

}  // namespace ephor::display
