#pragma once
// Kinematics of the Unimation PUMA 560 in millimetres: forward kinematics and
// the closed-form inverse (all up to 8 solutions) for the standard
// Denavit-Hartenberg model.
//
// Model: Peter Corke, Robotics Toolbox for MATLAB, mdl_puma560 (standard DH,
// Paul & Zhang 1986 kinematic figures):
//   link  theta  d [m]    a [m]   alpha   qlim [deg]
//    1     q1    0        0       +pi/2   [-160, 160]
//    2     q2    0        0.4318   0      [ -45, 225]
//    3     q3    0.15005  0.0203  -pi/2   [-225,  45]
//    4     q4    0.4318   0       +pi/2   [-110, 170]
//    5     q5    0        0       -pi/2   [-100, 100]
//    6     q6    0        0        0      [-266, 266]
// Frame 0 (the "base frame" here) is on the column axis at the height of the
// shoulder axis; frames 4, 5 and 6 share their origin (the wrist centre). The
// tool tip is `tool_length_mm` from the flange along z6 (the approach axis).
//
// Velocity and acceleration limits: mdl_puma560 has none, and we could not
// verify a published per-joint table here, so these are our own conservative
// choice (default_limits()): 1 rad/s for the three arm joints, 2 rad/s for the
// wrist, 2 and 4 rad/s^2. They are well below what the PUMA 560's motors are
// usually credited with; with the 300 mm/s tool-speed cap they bind close to
// the column (joint 1), near wrist singularities and in configuration changes,
// which is where the paper's "scale the motion down" check matters.

#include <array>
#include <optional>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace ephor::arm {

using Joints = Eigen::Matrix<double, 6, 1>;  // rad, PUMA 560 joint order

struct JointLimits {
  Joints q_min;    // rad
  Joints q_max;    // rad
  Joints qd_max;   // rad/s (symmetric)
  Joints qdd_max;  // rad/s^2 (symmetric)

  bool within(const Joints& q, double tolerance_rad = 1e-9) const;
};

// Standard DH parameters of one link, lengths in mm.
struct DhLink {
  double d_mm;
  double a_mm;
  double alpha_rad;
};

class Puma560 {
 public:
  static constexpr double kA2Mm = 431.8;
  static constexpr double kD3Mm = 150.05;
  static constexpr double kA3Mm = 20.3;
  static constexpr double kD4Mm = 431.8;

  // tool_length_mm: flange to tool tip along z6, mm (>= 0).
  explicit Puma560(double tool_length_mm = 0.0, JointLimits limits = default_limits());

  static JointLimits default_limits();
  static const std::array<DhLink, 6>& dh();

  // Standard poses of mdl_puma560, rad.
  static Joints qz();  // zero angles: arm horizontal, forearm up
  static Joints qr();  // ready: arm straight up
  static Joints qs();  // stretch: arm horizontal
  static Joints qn();  // nominal: a dextrous working pose (q3 = pi, outside qlim by 2 pi)

  // Frames 0..6 in the base frame (mm): [0] is identity, [i] is frame i.
  std::array<Eigen::Isometry3d, 7> link_frames(const Joints& q) const;
  // Flange (frame 6) pose in the base frame, mm.
  Eigen::Isometry3d flange(const Joints& q) const;
  // Tool tip pose in the base frame, mm: the flange moved tool_length along z6.
  Eigen::Isometry3d forward(const Joints& q) const;

  // Every joint vector within the limits that puts the tool at `tool_pose`
  // (base frame, mm): up to 8 (shoulder left/right x elbow up/down x wrist
  // flip). Angles are wrapped by 2 pi into the limits (preferring the
  // representation nearest zero). Empty when out of reach. At the wrist
  // singularity (q5 = 0) q4 is set to 0 and q6 carries the whole roll.
  std::vector<Joints> inverse(const Eigen::Isometry3d& tool_pose) const;

  // The solution closest to `current` (max over joints of the angular change,
  // each joint's 2 pi representation chosen within limits nearest current),
  // or nullopt when unreachable.
  std::optional<Joints> nearest_inverse(const Eigen::Isometry3d& tool_pose,
                                        const Joints& current) const;

  const JointLimits& limits() const { return limits_; }
  double tool_length_mm() const { return tool_length_mm_; }

 private:
  // Solutions by branch, not yet wrapped into limits.
  std::vector<Joints> raw_inverse(const Eigen::Isometry3d& tool_pose) const;

  double tool_length_mm_;
  JointLimits limits_;
};

// Wraps `angle` by multiples of 2 pi into [lo, hi], choosing the value
// nearest `reference`; nullopt when no representation fits.
std::optional<double> wrap_into(double angle, double lo, double hi, double reference);

}  // namespace ephor::arm
