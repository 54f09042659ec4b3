#pragma once
// ArmConfiguration: whether the PUMA can reach a tool-down point without
// changing its arm configuration (shoulder left/right, elbow up/down).
//
// Why: the arm stands at the field centre and joint 1 is limited to +-160
// deg, so neither configuration covers the whole field (the normal one ~86 %
// of it, the reach-over one ~85 %). A point outside the current
// configuration's region is reached only by an OMPL joint-space path that
// swings the tool over the top: 12-14 s instead of the ~2-4 s the
// straight-line model predicts (ephor-arm, procs/shared/arm/README.md). The planner
// asks this before trusting its straight-line intercept time.
//
// Pure kinematics (common/arm), no LCM: about 5 us per question.

#include <optional>

#include "common/arm/arm_workcell.h"
#include "common/geometry/workcell.h"
#include "procs/shepherd/planner/herd_types.h"

namespace ephor::planner {

class ArmConfiguration {
 public:
  explicit ArmConfiguration(const geometry::Workcell& cell);

  // The configuration of joints q: bit 0 = the wrist centre lies behind the
  // shoulder's reach direction (reach-over), bit 1 = elbow below the
  // shoulder-wrist line.
  int of(const JointAngles& q) const;

  // True when the tool, pointing down with orientation theta (rad) at
  // (x, y, z) of F (mm), has inverse-kinematics solutions within the joint
  // limits but none in the configuration of q: the move needs a
  // configuration change. False when the point is reachable as the arm is,
  // or not reachable at all (other rules reject such points).
  bool needs_switch(const JointAngles& q, double x_mm, double y_mm, double z_mm,
                    double theta_rad) const;

  // True when ephor-arm cannot follow the straight line from where q puts
  // the tool to the tool-down point (x, y, z), theta, without a jump of the
  // joints: the line crosses joint 1's +-160 deg wedge (or a wrist joint's
  // limit) even though both ends are in q's configuration, so the arm takes
  // a joint-space path around (12-15 s on the full system, like a
  // configuration change). Walks the line every `step_mm` with the same
  // arm::ToolLine as ephor-arm's Cartesian check. A point out of reach also returns
  // true; the column keep-out is FieldRules' business.
  bool line_needs_detour(const JointAngles& q, double x_mm, double y_mm, double z_mm,
                         double theta_rad, double step_mm = 40.0) const;

  // How far joint 1 turns, rad, for the tool to get from where q puts it to
  // the tool-down point (x, y, z), theta, in q's configuration: the nearest
  // such solution's joint 1 minus q's. Positive: the tool goes round the
  // column counter-clockwise seen from above. Joint 1 cannot pass its
  // +-160 deg, so this also says which way round the column the arm has to
  // go: the other way crosses the wedge. nullopt when the point needs a
  // configuration change or is out of reach.
  std::optional<double> joint1_turn_rad(const JointAngles& q, double x_mm, double y_mm, double z_mm,
                                        double theta_rad) const;

 private:
  int of(const arm::Joints& q) const;

  geometry::Workcell cell_;
  arm::Puma560 puma_;
};

}  // namespace ephor::planner
