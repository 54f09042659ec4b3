#pragma once
// The scan planner's plan (paper 004, sections 1 and 5): the regular raster
// of stripes over a region ("stepping the range finder in 10 mm steps over
// the region of interest"), each stripe's projector pose and the joint
// readings that put it there by the software's model (the calibration's
// zero references, C_T and S_T), checked before the arm moves: every
// corner of the region and every stripe within the PUMA's reach and joint
// limits and clear of the table and the pedestal as ephor-arm will check it
// (common/motion/arm_collision_checker.h).
//
// Units: mm, rad; the table frame of common/stripe/scan_geometry.h.

#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "common/geometry/workcell.h"
#include "common/stripe/scan_geometry.h"
#include "common/stripe/true_arm.h"

namespace ephor::stripe {

class PlanError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct RasterPlan {
  RasterSpec spec;
  std::vector<Eigen::Isometry3d> projector_poses;  // one per stripe, table frame
  std::vector<arm::Joints> goals;                  // joint readings per stripe
};

// "X0,Y0,X1,Y1" (mm) -> the region of `spec`; throws PlanError naming the
// problem (not four numbers, not finite, x1 <= x0 or y1 <= y0).
void parse_region(const std::string& text, RasterSpec& spec);

// Plans the raster from the joints `start`. Throws PlanError with one line:
// a bad step or region, "region corner (x0, y1) = (-200, 300) mm is out of
// reach: ..." (the first corner, in the order (x0, y0), (x1, y0), (x0, y1),
// (x1, y1), where the projector cannot look straight down from the scan
// height), or the first stripe that cannot be reached.
RasterPlan plan_raster(const RasterSpec& spec, const geometry::Workcell& workcell,
                       const TrueArm& model, const SensorCalibration& calibration,
                       const arm::Joints& start = StripeWorkcell::reference_joints());

}  // namespace ephor::stripe
