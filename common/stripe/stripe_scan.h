#pragma once
// One scan end to end without the bus (what the scan planner, arm, sim,
// stripe and range processes do together): for each projector pose, the
// joint readings the nominal model gives for it (nearest the previous
// readings), the world's image there, the range finder's points. The cloud
// is in mm in the table frame.

#include <cstdint>
#include <vector>

#include "common/stripe/range_finder.h"
#include "common/stripe/stripe_world.h"

namespace ephor::stripe {

struct ScanStripe {
  arm::Joints joints;              // readings the image was taken at
  std::vector<RangePoint> points;  // this stripe's points, table frame
};

struct ScanResult {
  std::vector<ScanStripe> stripes;
  int unreachable = 0;     // poses the arm could not reach (skipped)
  double render_s = 0.0;   // wall time spent rendering (the simulated camera)
  double process_s = 0.0;  // wall time image -> 3-D points (extraction + collineation)

  std::vector<Eigen::Vector3d> cloud() const;
  size_t point_count() const;
};

// `planning_cage` is the calibration the planner uses to place the projector
// (the range finder's own). Image seeds are seed, seed + 1, ...
ScanResult run_scan(const StripeWorld& world, const RangeFinder& finder,
                    const std::vector<Eigen::Isometry3d>& projector_poses, std::uint64_t seed,
                    arm::Joints start = StripeWorkcell::reference_joints());

}  // namespace ephor::stripe
