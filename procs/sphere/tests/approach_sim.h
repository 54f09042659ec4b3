#pragma once
// The sphere system's closed loop without LCM or real time (issue 15's
// approach): the ranger's world (RangerWorld), the locator (SphereLocator
// on each complete window) and the guidance (SphereGuidance) called in the
// order and with the timing the processes have: the estimate of window k
// is made at its end, (k+1)W, and its command takes effect at (k+2)W. One
// approach from start_m takes well under a second of CPU, so seeded sweeps
// (ephor-bench-sphere-approach) and a unit test can fly many.

#include <cstdint>
#include <string>

#include "common/sphere/guidance/sphere_guidance.h"
#include "common/sphere/sphere_locator.h"
#include "common/sphere/world/ranger_world.h"

namespace ephor::sphere {

struct ApproachSimConfig {
  RangerWorldConfig world;  // approaches = 1; seed, start, drift, noise, max_s
  LocatorConfig locator;
  GuidanceConfig guidance;
  bool verbose = false;  // print each window (estimate, truth, innovation)
};

// start_m along the boresight, Table 1's drift for it, give up after max_s.
ApproachSimConfig approach_sim_config(uint64_t seed, double start_m, double max_s = 300.0);

struct ApproachResult {
  bool judged = false;
  CaptureVerdict verdict;
  int windows = 0;
  int estimates = 0;  // windows with an estimate
  int no_estimates = 0;
  int rejected = 0;      // refused by the filter (beyond 20 sigma)
  int downweighted = 0;  // beyond its 99.9 % gate: used with an inflated sigma
  int reinitialised = 0;
  double estimate_rms_m[3] = {0, 0, 0};  // locator against truth at the estimate's time
  double filter_rms_m[3] = {0, 0, 0};    // filter against truth at the same times
  double estimate_cpu_us_max = 0.0;
};

ApproachResult fly_approach(const ApproachSimConfig& config);

}  // namespace ephor::sphere
