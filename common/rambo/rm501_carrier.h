#pragma once
// The target carried by a second, smaller arm, as in the paper's laboratory
// (section 2: the target moved by a Mitsubishi RM-501 "Movemaster"): the
// other of the simulator's two target motions beside the free-floating
// TumblingBody. Ground truth only: for the simulator, tests and benchmarks.
//
// The arm: five revolute joints, waist (q1, about the vertical), shoulder
// (q2), elbow (q3) and wrist pitch (q4) about parallel horizontal axes, wrist
// roll (q5) about the hand's axis. In the arm's own frame (z up along the
// waist axis, x forward at q1 = 0), with phi2 = q2, phi3 = q2 + q3 and
// phi4 = q2 + q3 + q4 the link angles above the horizontal:
//   reach r = a2 cos phi2 + a3 cos phi3 + hand cos phi4
//   height z = d1 + a2 sin phi2 + a3 sin phi3 + hand sin phi4
//   flange = Rz(q1) Ry(-phi4) Rx(q5) at (r cos q1, r sin q1, z)
// (the flange's x axis is the hand's axis). All zeros: the arm stretched out
// horizontally along x.
//
// Where the numbers come from: the RM-501's joint spans and link lengths as
// Mitsubishi's Movemaster spec sheets give them, recalled (not checked
// against a copy here): waist 300 deg, shoulder 130 deg, elbow 90 deg, wrist
// pitch +-90 deg, wrist roll +-180 deg; upper arm a2 = 220 mm, forearm a3 =
// 160 mm. The largest joint speeds (120, 72, 109, 100, 163 deg/s) are the
// Movemaster figures as recalled likewise. Ours: the shoulder's height d1 =
// 250 mm, the hand (wrist pitch axis to flange) 100 mm, where the shoulder's
// and elbow's spans sit (shoulder -30..100 deg above the horizontal, elbow
// -90..0 deg from the upper arm's line), the target's centre 200 mm beyond
// the flange on the hand's axis (clear of the 240 x 180 x 140 mm box), and
// the arm's base placed, turned to face the PUMA, so that at its nominal
// joints the target is at the free-floating motion's start pose.
//
// The motion: each joint swings smoothly about its nominal angle,
// q_i(t) = nominal_i + A_i sin(w_i t + p_i), frequencies and phases drawn
// from the seed (incommensurate: the target translates and rotates smoothly
// but never with a constant twist), amplitudes and rates scaled by
// speed_scale (1 = swings of 5, 4, 5, 8 and 60 deg; wrist roll up to about
// 4 deg/s; the target turning at up to about 5 deg/s and its centre moving
// up to about 20 mm/s over a span of up to about 200 mm).

#include <array>
#include <cstdint>

#include <Eigen/Geometry>

namespace ephor::rambo {

class Rm501Carrier {
 public:
  using Joints = Eigen::Matrix<double, 5, 1>;  // q1..q5, rad

  // Joint limits (rad) and largest speeds (rad/s); see above.
  static Joints lower_limits();
  static Joints upper_limits();
  static Joints max_speeds();
  static constexpr double kShoulderHeightMm = 250.0;  // d1
  static constexpr double kUpperArmMm = 220.0;        // a2
  static constexpr double kForearmMm = 160.0;         // a3
  static constexpr double kHandMm = 100.0;            // wrist pitch axis to flange
  static constexpr double kMountMm = 200.0;           // flange to the target's origin

  // The arm placed so that at its nominal joints the target is at
  // `target_pose0` (target frame -> PUMA base, mm); seed and speed_scale as
  // above. Throws std::invalid_argument for a speed_scale <= 0 or one whose
  // swings leave the joint limits or exceed the joint speeds.
  Rm501Carrier(const Eigen::Isometry3d& target_pose0, std::uint64_t seed, double speed_scale = 1.0);

  // The flange in the arm's own frame (mm).
  static Eigen::Isometry3d flange_in_arm(const Joints& q);
  // The arm's links as a chain of points in its own frame (mm): the waist's
  // foot on the floor, the shoulder, the elbow, the wrist (pitch axis), the
  // flange. For drawing it (the camera frames, the page).
  static std::array<Eigen::Vector3d, 5> chain_in_arm(const Joints& q);
  // The same in the PUMA's base at t, with the target's origin (the end of
  // the mount) appended: 6 points, mm.
  std::array<Eigen::Vector3d, 6> chain(double t_s) const;
  // Each link's radius for drawing, mm (ours: the Movemaster's castings
  // roughly; the mount a rod), link k joining chain point k to k + 1.
  static constexpr std::array<double, 5> kLinkRadiusMm{60.0, 40.0, 32.0, 25.0, 12.0};

  Joints joints(double t_s) const;       // rad
  Joints joint_rates(double t_s) const;  // rad/s
  // The target frame in the PUMA's base at t (mm).
  Eigen::Isometry3d pose(double t_s) const;
  // The target's angular velocity at t, target frame, rad/s (from the joint
  // rates, by a central difference of 1 ms).
  Eigen::Vector3d body_rates(double t_s) const;

  const Joints& nominal() const { return nominal_; }
  const Joints& amplitudes() const { return amplitude_; }
  const Eigen::Isometry3d& arm_in_base() const { return arm_in_base_; }

 private:
  Eigen::Isometry3d arm_in_base_ = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d target_in_flange_ = Eigen::Isometry3d::Identity();
  Joints nominal_, amplitude_, omega_, phase_;
};

}  // namespace ephor::rambo
