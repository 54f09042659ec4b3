#include "common/sphere/sphere_locator.h"

#include <ctime>
#include <stdexcept>

namespace ephor::sphere {
namespace {

double thread_cpu_us() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) * 1e6 + static_cast<double>(ts.tv_nsec) * 1e-3;
}

ScanLineExtentConfig sle_config(const LocatorConfig& c) {
  ScanLineExtentConfig s = c.variant == Variant::kPaper ? ScanLineExtentConfig::paper()
                                                        : ScanLineExtentConfig::improved();
  s.gate.background_range_m = c.background_range_m;
  return s;
}

SphereFitterConfig fit_config(const LocatorConfig& c) {
  SphereFitterConfig f =
      c.variant == Variant::kPaper ? SphereFitterConfig::paper() : SphereFitterConfig::improved();
  f.gate.background_range_m = c.background_range_m;
  return f;
}

}  // namespace

Algorithm parse_algorithm(const std::string& word) {
  if (word == "sle") return Algorithm::kScanLineExtent;
  if (word == "fit") return Algorithm::kSphereFitting;
  throw std::invalid_argument("unknown algorithm '" + word + "' (sle or fit)");
}

Variant parse_variant(const std::string& word) {
  if (word == "paper") return Variant::kPaper;
  if (word == "improved") return Variant::kImproved;
  throw std::invalid_argument("unknown variant '" + word + "' (paper or improved)");
}

const char* to_string(Algorithm a) { return a == Algorithm::kScanLineExtent ? "sle" : "fit"; }
const char* to_string(Variant v) { return v == Variant::kPaper ? "paper" : "improved"; }

SphereLocator::SphereLocator(const LocatorConfig& config)
    : config_(config), sle_(sle_config(config)), fitter_(fit_config(config)) {}

Estimate SphereLocator::locate(const Window& window, double* cpu_us) const {
  const double start = thread_cpu_us();
  Estimate e = config_.algorithm == Algorithm::kScanLineExtent ? sle_.locate(window)
                                                               : fitter_.locate(window);
  if (cpu_us) *cpu_us = thread_cpu_us() - start;
  return e;
}

}  // namespace ephor::sphere
