#pragma once
// Direction-dependent error (paper 004, section 5): "If an object is scanned
// twice with the ranger approaching it from different directions, and we
// notice a shift in the apparent position of the object, the amount of that
// shift is [direction]-dependent error. ... we use a pyramid for a target ...
// we can vary the direction of approach, direction of scan, and distance from
// the object." Here: the pyramid scene's apex located (PyramidApex) from a
// sweep of stripes per view; the error is each apex's distance from the
// mean of all views' apexes (worst over views), beside the distance from the
// true apex.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common/stripe/range_finder.h"
#include "common/stripe/stripe_world.h"

namespace ephor::stripe {

struct ApexView {
  Eigen::Vector3d approach;     // unit, from the apex towards the sensor (table frame)
  Eigen::Vector3d stripe_hint;  // the stripe's direction (the scan goes across it)
  double distance_mm = 300.0;   // projector to apex
  std::string label;
};

// Straight down and tilted 25 deg from each of +-x, +-y; stripes along x and
// along y; 270 and 330 mm: 20 views.
std::vector<ApexView> section5_views();

struct DirectionError {
  std::vector<std::optional<Eigen::Vector3d>> apex_mm;  // per view; nullopt: not located
  Eigen::Vector3d mean_mm = Eigen::Vector3d::Zero();
  double worst_from_mean_mm = 0.0;  // the direction-dependent error
  double worst_from_truth_mm = 0.0;
  int located = 0;
  int unreachable_poses = 0;
};

// Sweeps of 11 stripes 10 mm apart per view. `true_apex_mm` (the scene's,
// table frame) starts the face split and scores the absolute error.
DirectionError measure_direction_error(const StripeWorld& world, const RangeFinder& finder,
                                       const std::vector<ApexView>& views,
                                       const Eigen::Vector3d& true_apex_mm, std::uint64_t seed);

}  // namespace ephor::stripe
