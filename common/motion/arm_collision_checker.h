#pragma once
// ArmCollisionChecker: is a PUMA 560 configuration clear of the work cell?
// The obstacles are the table (z = 0 of F), the pedestal the arm stands on
// (a vertical cylinder of pedestal_radius around the column, from the table up
// to the base frame) and, per motion, a lowest allowed tool-tip height (so
// that free travel in the elevation plane does not sweep through the sheep).
//
// The arm is modelled by points along its centre lines (upper arm, elbow
// offset, forearm, tool) and clearances that stand for the links' thickness.
// That is coarse but conservative enough for a simulated cell; a real cell
// would use meshes (e.g. FCL through OMPL's MoveIt integration).

#include <limits>
#include <optional>
#include <string>

#include "common/arm/puma560.h"
#include "common/geometry/workcell.h"

namespace ephor::arm {

struct CollisionConfig {
  double tip_table_clearance_mm = 10.0;   // tool tip above the table, mm
  double link_table_clearance_mm = 40.0;  // elbow, forearm, wrist above the table, mm
  double pedestal_clearance_mm = 30.0;    // link surface to pedestal surface, mm
  // The shoulder housing sits on the pedestal: the first part of the upper
  // arm is not checked against it, mm.
  double shoulder_housing_mm = 150.0;
};

class ArmCollisionChecker {
 public:
  ArmCollisionChecker(const Puma560& arm, const geometry::Workcell& cell,
                      CollisionConfig config = {});

  // nullopt when clear; otherwise what collides, e.g. "tool tip 4.0 mm above
  // the table (< 10.0)". min_tip_z_mm: lowest allowed tip height in F, mm.
  std::optional<std::string> collision(
      const Joints& q, double min_tip_z_mm = -std::numeric_limits<double>::infinity()) const;

  bool clear(const Joints& q,
             double min_tip_z_mm = -std::numeric_limits<double>::infinity()) const {
    return !collision(q, min_tip_z_mm).has_value();
  }

 private:
  Puma560 arm_;
  geometry::Workcell cell_;
  CollisionConfig config_;
};

}  // namespace ephor::arm
