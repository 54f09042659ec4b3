#pragma once
// CalibrationPlan: where ephor-calibrate puts the tool tip (paper 003,
// section 5: the arm is moved to known points and they are found in the
// image; three give the object plane's 2 x 3 matrix, a fourth the elevation
// plane's). We take more than the minimum in both planes so the least-squares
// fit averages the spot-finding noise and the residuals show a bad point.
//
// Frames: field frame F, mm (common/geometry/workcell.h); tool pointing
// straight down (common/arm/arm_workcell.h), orientation theta = 0.
//
// Immutable after construction.

#include <string>
#include <vector>

#include <Eigen/Core>

#include "common/calibration/field_calibration.h"
#include "common/geometry/workcell.h"

namespace ephor::calibrate {

// One stop of the tool tip. `measure` false: a via point only (the tool is
// lowered into the object plane from above, not swept across the table).
struct CalibrationStop {
  Eigen::Vector3d tip_mm;  // tool tip in F, mm
  calibration::Plane plane = calibration::Plane::kObject;
  bool measure = true;
};

struct CalibrationPlanConfig {
  // Object-plane points: the field corners moved this far inwards, plus the
  // middles of the two long edges (6 points spread over the field), mm.
  double object_inset_mm = 100.0;
  // Elevation-plane points: a rectangle about the field centre of these half
  // sizes (the elevation plane is reachable only ~345 mm out from the
  // column), mm.
  double elevation_half_x_mm = 360.0;
  double elevation_half_y_mm = 260.0;
  // Go up to the elevation plane between object-plane points.
  bool approach_from_elevation = true;
};

class CalibrationPlan {
 public:
  // The standard plan for `cell`. Throws std::invalid_argument naming the
  // first point the tool cannot reach pointing down, or a bad config value.
  explicit CalibrationPlan(const geometry::Workcell& cell, CalibrationPlanConfig config = {});
  // Any points (each must be reachable, at least 3 object-plane and 1
  // elevation-plane measured stops); same errors.
  CalibrationPlan(const geometry::Workcell& cell, std::vector<CalibrationStop> stops);

  // In the order to visit them (elevation plane first: the arm starts parked there).
  const std::vector<CalibrationStop>& stops() const { return stops_; }
  int measured(calibration::Plane plane) const;

 private:
  void check(const geometry::Workcell& cell) const;
  std::vector<CalibrationStop> stops_;
};

}  // namespace ephor::calibrate
