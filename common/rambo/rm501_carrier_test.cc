#include "common/rambo/rm501_carrier.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "common/rambo/rambo_cell.h"

namespace ephor::rambo {
namespace {

constexpr double kDeg = M_PI / 180.0;

double angle_between(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return Eigen::AngleAxisd(a.transpose() * b).angle();
}

// Hand-checked: stretched out level, the flange is a2 + a3 + hand out along
// x at the shoulder's height; the waist at 90 deg turns that onto y; the
// upper arm straight up with the rest level puts the flange a2 higher and
// a2 nearer; the roll turns the flange about its own x.
TEST(Rm501Carrier, ForwardKinematicsOfHandCheckedPoses) {
  using C = Rm501Carrier;
  const double reach = C::kUpperArmMm + C::kForearmMm + C::kHandMm;  // 480 mm
  Eigen::Isometry3d f = C::flange_in_arm(C::Joints::Zero());
  EXPECT_LT((f.translation() - Eigen::Vector3d(reach, 0, C::kShoulderHeightMm)).norm(), 1e-9);
  EXPECT_LT(angle_between(f.linear(), Eigen::Matrix3d::Identity()), 1e-12);
  C::Joints q = C::Joints::Zero();
  q[0] = 90 * kDeg;
  f = C::flange_in_arm(q);
  EXPECT_LT((f.translation() - Eigen::Vector3d(0, reach, C::kShoulderHeightMm)).norm(), 1e-9);
  q << 0, 90 * kDeg, -90 * kDeg, 0, 30 * kDeg;
  f = C::flange_in_arm(q);
  EXPECT_LT((f.translation() -
             Eigen::Vector3d(C::kForearmMm + C::kHandMm, 0, C::kShoulderHeightMm + C::kUpperArmMm))
                .norm(),
            1e-9);
  EXPECT_LT((f.linear().col(0) - Eigen::Vector3d::UnitX()).norm(), 1e-12);  // hand still level
  EXPECT_NEAR(std::atan2(f.linear()(2, 1), f.linear()(1, 1)), 30 * kDeg, 1e-12);
}

// The drawn chain: its flange is the forward kinematics' flange, its links
// are the arm's lengths, and in the PUMA's base it ends at the target's
// origin, the mount's length beyond the flange.
TEST(Rm501Carrier, TheDrawnChainFollowsTheForwardKinematics) {
  using C = Rm501Carrier;
  C::Joints q;
  q << 20 * kDeg, 60 * kDeg, -60 * kDeg, 10 * kDeg, 45 * kDeg;
  const auto p = C::chain_in_arm(q);
  EXPECT_LT((p[4] - C::flange_in_arm(q).translation()).norm(), 1e-9);
  EXPECT_NEAR((p[1] - p[0]).norm(), C::kShoulderHeightMm, 1e-9);
  EXPECT_NEAR((p[2] - p[1]).norm(), C::kUpperArmMm, 1e-9);
  EXPECT_NEAR((p[3] - p[2]).norm(), C::kForearmMm, 1e-9);
  EXPECT_NEAR((p[4] - p[3]).norm(), C::kHandMm, 1e-9);
  const RamboCell cell = RamboCell::make(4);
  const C arm(cell.draw_motion(2, 2.0, 1.0).pose0, 2);
  for (double t : {0.0, 13.0, 77.0}) {
    const auto c = arm.chain(t);
    EXPECT_LT((c[5] - arm.pose(t).translation()).norm(), 1e-9) << t;
    EXPECT_NEAR((c[5] - c[4]).norm(), C::kMountMm, 1e-9) << t;
    EXPECT_NEAR(c[0].z() - c[1].z(), -C::kShoulderHeightMm, 1e-9) << t;  // the waist upright
  }
}

// The carried target starts where the free-floating one does, and over two
// minutes (10 ms samples) its joints stay within the RM-501's limits and
// speeds, its motion is smooth (velocity and angular velocity change little
// from sample to sample: no jumps) and it is not a constant twist (its
// angular velocity in the target frame turns and changes size, and it
// translates).
TEST(Rm501Carrier, CarriedTargetMovesSmoothlyWithinTheArmsLimits) {
  const RamboCell cell = RamboCell::make(4);
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    const Eigen::Isometry3d pose0 = cell.draw_motion(seed, 2.0, 1.0).pose0;
    const Rm501Carrier arm(pose0, seed);
    const Eigen::Isometry3d start = arm.pose(0.0);
    // At t = 0 the joints are off nominal by their phases: near the start.
    EXPECT_LT((start.translation() - pose0.translation()).norm(), 200.0) << "seed " << seed;

    const double dt = 0.01;
    double max_dv = 0, max_dw = 0, max_speed = 0, max_rate = 0;
    double w_min = 1e9, w_max = 0, axis_turn = 0;
    Eigen::Vector3d w_first = arm.body_rates(0.0);
    Eigen::Vector3d p_prev = start.translation(), v_prev = Eigen::Vector3d::Zero();
    Eigen::Vector3d w_prev = w_first;
    Eigen::Vector3d lo = start.translation(), hi = start.translation();
    for (int k = 1; k <= 12000; ++k) {
      const double t = k * dt;
      const Rm501Carrier::Joints q = arm.joints(t), qd = arm.joint_rates(t);
      for (int i = 0; i < 5; ++i) {
        ASSERT_GE(q[i], Rm501Carrier::lower_limits()[i]) << "joint " << i + 1 << " t " << t;
        ASSERT_LE(q[i], Rm501Carrier::upper_limits()[i]) << "joint " << i + 1 << " t " << t;
        ASSERT_LE(std::abs(qd[i]), Rm501Carrier::max_speeds()[i]) << "joint " << i + 1;
      }
      const Eigen::Isometry3d p = arm.pose(t);
      const Eigen::Vector3d v = (p.translation() - p_prev) / dt;
      const Eigen::Vector3d w = arm.body_rates(t);
      if (k > 1) max_dv = std::max(max_dv, (v - v_prev).norm());
      max_dw = std::max(max_dw, (w - w_prev).norm());
      max_speed = std::max(max_speed, v.norm());
      max_rate = std::max(max_rate, w.norm());
      w_min = std::min(w_min, w.norm());
      w_max = std::max(w_max, w.norm());
      if (w.norm() > 1e-6 && w_first.norm() > 1e-6)
        axis_turn = std::max(
            axis_turn, std::acos(std::clamp(w.normalized().dot(w_first.normalized()), -1.0, 1.0)));
      lo = lo.cwiseMin(p.translation());
      hi = hi.cwiseMax(p.translation());
      p_prev = p.translation();
      v_prev = v;
      w_prev = w;
    }
    // Smooth: in 10 ms the velocity changes by < 0.1 mm/s and the angular
    // velocity by < 0.02 deg/s (accelerations under 10 mm/s^2 and 2 deg/s^2).
    EXPECT_LT(max_dv, 0.1) << "seed " << seed;
    EXPECT_LT(max_dw, 0.02 * kDeg) << "seed " << seed;
    // Slow enough for the PUMA to follow, like the free-floating 2 deg/s.
    EXPECT_LT(max_speed, 25.0) << "seed " << seed;
    EXPECT_LT(max_rate, 8.0 * kDeg) << "seed " << seed;
    // Not a constant twist: the rotation's axis turns by more than 30 deg
    // and its rate varies by more than 1 deg/s; the centre moves > 50 mm.
    EXPECT_GT(axis_turn, 30 * kDeg) << "seed " << seed;
    EXPECT_GT(w_max - w_min, 1.0 * kDeg) << "seed " << seed;
    EXPECT_GT((hi - lo).maxCoeff(), 50.0) << "seed " << seed;
    std::fprintf(stderr,
                 "seed %d: centre within %.0f x %.0f x %.0f mm, up to %.1f mm/s; rate %.2f-%.2f "
                 "deg/s, axis turns up to %.0f deg\n",
                 static_cast<int>(seed), hi.x() - lo.x(), hi.y() - lo.y(), hi.z() - lo.z(),
                 max_speed, w_min / kDeg, w_max / kDeg, axis_turn / kDeg);
  }
}

TEST(Rm501Carrier, NominalJointsPutTheTargetAtTheStartPose) {
  const Eigen::Isometry3d pose0 = RamboCell::make(4).draw_motion(5, 2.0, 1.0).pose0;
  const Rm501Carrier arm(pose0, 5);
  // The pose at the nominal joints, by the same chain as pose(t).
  const Eigen::Isometry3d flange = arm.arm_in_base() * Rm501Carrier::flange_in_arm(arm.nominal());
  const Eigen::Isometry3d at_nominal = flange * (arm.pose(0.0).inverse() * arm.arm_in_base() *
                                                 Rm501Carrier::flange_in_arm(arm.joints(0.0)))
                                                    .inverse();
  EXPECT_LT((at_nominal.translation() - pose0.translation()).norm(), 1e-6);
  EXPECT_LT(angle_between(at_nominal.linear(), pose0.linear()), 1e-9);
  EXPECT_THROW(Rm501Carrier(pose0, 5, 0.0), std::invalid_argument);
  EXPECT_THROW(Rm501Carrier(pose0, 5, 1000.0), std::invalid_argument);  // beyond the joint speeds
}

}  // namespace
}  // namespace ephor::rambo
