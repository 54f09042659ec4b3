#pragma once
// Does the arm serve the work cell this planner plans for?
//
// The planner and ephor-arm each take the work cell from the manifest's
// --workcell file. Given different files (or one process built with other
// defaults), the arm lowers the tool to heights the planner does not expect:
// the planner then never sees its "stay" goals done and resends them at the
// frame rate forever (issue 13). ARM_STATE says on which plane the last
// motion ended and where the tool tip is (z in F, mm): at rest after a
// motion on a plane the tip is on that plane to within the servo's settling,
// so a larger difference means the two work cells disagree. The planner
// then says so once and stops planning until they agree again.

#include <optional>
#include <string>

#include "common/geometry/workcell.h"
#include "procs/shepherd/planner/herd_types.h"

namespace ephor::planner {

class WorkcellAgreement {
 public:
  // tolerance_mm: how far the resting tool tip may be from the plane's height.
  explicit WorkcellAgreement(const geometry::Workcell& cell, double tolerance_mm = 5.0);

  // One ARM_STATE: the plane of the last completed motion (nullopt while
  // moving or before any), and the tool tip's height in F, mm. Returns a
  // message to log when the verdict changes (disagreeing, or agreeing again),
  // nothing otherwise: the log says it once, not at the state rate.
  std::optional<std::string> update(std::optional<Plane> plane, double tip_z_mm);

  // False from the first disagreement until the arm rests on a plane at the
  // planner's height again.
  bool agrees() const { return agrees_; }

 private:
  geometry::Workcell cell_;
  double tolerance_mm_;
  bool agrees_ = true;
};

// Empty when the calibration's plane heights match the work cell's (within
// 1 mm); otherwise why not, naming both heights. A calibration measured for
// another work cell maps image goals onto the wrong plane.
std::string calibration_disagreement(const geometry::Workcell& cell, double calibration_object_z_mm,
                                     double calibration_elevation_z_mm);

}  // namespace ephor::planner
