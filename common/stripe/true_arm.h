#pragma once
// The PUMA 560 as it really is (paper 004, section 3): the joint readings
// differ from the physical angles by zero-reference errors ("any joint that
// deviates from its nominal placement at the time POTCAL is initiated will
// have that deviation reproduced in all subsequent moves"), and the links
// differ from the nominal DH model by small errors no calibration here
// models. The same class is the software's model: nominal(), or nominal with
// the zero references a calibration found.
//
// Frames: the PUMA's base frame (common/arm/puma560.h), mm; joint readings in
// rad as the controller reports them.

#include <array>
#include <cstdint>

#include <Eigen/Geometry>

#include "common/arm/puma560.h"

namespace ephor::stripe {

struct ArmErrors {
  // Physical joint angle = reading + zero_offset (rad). Joint 1's error only
  // turns the whole world about the column (section 3: "we make no attempt
  // to correct joint 1"), so draw() leaves it zero.
  arm::Joints zero_offset_rad = arm::Joints::Zero();
  // Added to the nominal DH parameters of each link (d and a in mm, alpha in rad).
  std::array<arm::DhLink, 6> dh_error{};

  // Per-seed errors: zero references uniform in +-max_zero_deg on joints
  // 2-6; each link's d and a uniform in +-link_mm and alpha in +-twist_deg.
  static ArmErrors draw(std::uint64_t seed, double max_zero_deg = 1.0, double link_mm = 0.3,
                        double twist_deg = 0.05);
};

class TrueArm {
 public:
  explicit TrueArm(ArmErrors errors = {});
  static TrueArm nominal() { return TrueArm(); }
  // The nominal links with these zero references (what a calibration gives).
  static TrueArm with_zero_offsets(const arm::Joints& zero_offset_rad);

  // Flange (frame 6) in the base frame, mm, for the joint readings q (rad).
  Eigen::Isometry3d flange(const arm::Joints& q) const;

  const ArmErrors& errors() const { return errors_; }

 private:
  ArmErrors errors_;
  std::array<arm::DhLink, 6> dh_;
};

}  // namespace ephor::stripe
