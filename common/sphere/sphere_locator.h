#pragma once
// One entry point for the locator process and the offline tools: either of
// the paper's algorithms (Scan Line Extent or Sphere Fitting), as the paper
// wrote them or with the corrections beyond it, on one window of scan lines.

#include <string>

#include "common/sphere/scan_line_extent.h"
#include "common/sphere/scan_types.h"
#include "common/sphere/sphere_fitter.h"

namespace ephor::sphere {

enum class Algorithm { kScanLineExtent, kSphereFitting };
enum class Variant { kPaper, kImproved };

// "sle" / "fit" and "paper" / "improved"; throws std::invalid_argument naming the word.
Algorithm parse_algorithm(const std::string& word);
Variant parse_variant(const std::string& word);
const char* to_string(Algorithm a);
const char* to_string(Variant v);

struct LocatorConfig {
  Algorithm algorithm = Algorithm::kScanLineExtent;
  Variant variant = Variant::kImproved;
  double background_range_m = 50.0;  // returns at or beyond are background
};

class SphereLocator {
 public:
  explicit SphereLocator(const LocatorConfig& config);

  // The estimate, and in *cpu_us the thread CPU time it took (microseconds).
  Estimate locate(const Window& window, double* cpu_us = nullptr) const;

  const LocatorConfig& config() const { return config_; }

 private:
  LocatorConfig config_;
  ScanLineExtent sle_;
  SphereFitter fitter_;
};

}  // namespace ephor::sphere
