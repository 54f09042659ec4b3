#pragma once
// Number formatting shared by the display pages' state builders (the JSON
// of GET /api/state): small, and never NaN (which JSON cannot carry).

#include <cmath>
#include <cstdint>

namespace ephor::display {

// Rounded to `digits` decimals; NaN and infinities become 0. An x so large
// that x * 10^digits overflows (|x| above ~1e307 / 10^digits, a number from a
// corrupt message) is a whole number already and is kept as it is.
inline double rounded(double x, int digits) {
  if (!std::isfinite(x)) return 0.0;
  const double scale = std::pow(10.0, digits);
  const double r = std::round(x * scale) / scale;
  return std::isfinite(r) ? r : x;
}

// Rounded to 0.1 so the JSON stays small; NaN and infinities become 0.
inline double r1(double x) { return rounded(x, 1); }

// Age in ms of something received at `then_us` (wall clock, us), or -1 when never.
inline double age_ms(int64_t then_us, int64_t now_us) {
  return then_us == 0 ? -1.0 : static_cast<double>(now_us - then_us) / 1e3;
}

}  // namespace ephor::display
