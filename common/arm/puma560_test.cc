#include "common/arm/puma560.h"

#include <cmath>
#include <numbers>
#include <random>

#include <gtest/gtest.h>
#include <kdl/chain.hpp>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>

namespace ephor::arm {
namespace {

constexpr double kPi = std::numbers::pi;

Joints random_joints(std::mt19937& rng, const JointLimits& l) {
  Joints q;
  for (int i = 0; i < 6; ++i)
    q[i] = std::uniform_real_distribution<double>(l.q_min[i], l.q_max[i])(rng);
  return q;
}

double rotation_error(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return (a.linear() - b.linear()).cwiseAbs().maxCoeff();
}

bool same_modulo_2pi(const Joints& a, const Joints& b, double tol) {
  for (int i = 0; i < 6; ++i)
    if (std::abs(std::remainder(a[i] - b[i], 2.0 * kPi)) > tol) return false;
  return true;
}

// Poses near the three PUMA singularities lose the original branch
// numerically (several branches coincide); the round trip skips them.
bool near_singular(const Joints& q) {
  const double a2 = Puma560::kA2Mm, a3 = Puma560::kA3Mm, d4 = Puma560::kD4Mm;
  const double x1 = a2 * std::cos(q[1]) + a3 * std::cos(q[1] + q[2]) - d4 * std::sin(q[1] + q[2]);
  const double elbow = std::sin(q[2] - std::atan2(a3, d4));
  return std::abs(std::sin(q[4])) < 1e-3 || std::abs(x1) < 1e-2 || std::abs(elbow) < 1e-4;
}

TEST(Puma560Test, StandardPosesMatchCorkesModel) {
  // Values from the Robotics Toolbox (fkine of mdl_puma560), converted to mm.
  const Puma560 arm;
  const Eigen::Isometry3d tz = arm.forward(Puma560::qz());
  EXPECT_TRUE(tz.translation().isApprox(Eigen::Vector3d(452.1, -150.05, 431.8), 1e-9));
  EXPECT_LT(rotation_error(tz, Eigen::Isometry3d::Identity()), 1e-12);

  const Eigen::Isometry3d tr = arm.forward(Puma560::qr());
  EXPECT_TRUE(tr.translation().isApprox(Eigen::Vector3d(20.3, -150.05, 863.6), 1e-9));
  EXPECT_LT(rotation_error(tr, Eigen::Isometry3d::Identity()), 1e-12);

  const Eigen::Isometry3d ts = arm.forward(Puma560::qs());
  EXPECT_TRUE(ts.translation().isApprox(Eigen::Vector3d(863.6, -150.05, -20.3), 1e-9));
  Eigen::Matrix3d rs;
  rs << 0, 0, 1, 0, 1, 0, -1, 0, 0;  // approach axis along +x: arm stretched out
  EXPECT_LT((ts.linear() - rs).cwiseAbs().maxCoeff(), 1e-12);

  // fkine(qn) = [0 0 1 0.5963; 0 1 0 -0.1501; -1 0 0 -0.01435]
  const Eigen::Isometry3d tn = arm.forward(Puma560::qn());
  EXPECT_NEAR(tn.translation().x(), 596.3, 0.05);
  EXPECT_NEAR(tn.translation().y(), -150.05, 1e-9);
  EXPECT_NEAR(tn.translation().z(), -14.35, 0.01);
  EXPECT_LT((tn.linear() - rs).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(Puma560Test, ToolTipIsAlongApproachAxis) {
  const Puma560 arm(100.0);
  std::mt19937 rng(7);
  for (int n = 0; n < 100; ++n) {
    const Joints q = random_joints(rng, arm.limits());
    const Eigen::Isometry3d f = arm.flange(q);
    EXPECT_LT((arm.forward(q).translation() - (f.translation() + 100.0 * f.linear().col(2))).norm(),
              1e-9);
  }
}

TEST(Puma560Test, ForwardKinematicsAgreesWithOrocosKdl) {
  KDL::Chain chain;
  for (const DhLink& l : Puma560::dh())
    chain.addSegment(KDL::Segment(KDL::Joint(KDL::Joint::RotZ),
                                  KDL::Frame::DH(l.a_mm, l.alpha_rad, l.d_mm, 0.0)));
  KDL::ChainFkSolverPos_recursive fk(chain);
  const Puma560 arm;
  std::mt19937 rng(11);
  for (int n = 0; n < 1000; ++n) {
    const Joints q = random_joints(rng, arm.limits());
    KDL::JntArray jq(6);
    for (int i = 0; i < 6; ++i) jq(i) = q[i];
    KDL::Frame f;
    ASSERT_GE(fk.JntToCart(jq, f), 0);
    const Eigen::Isometry3d mine = arm.flange(q);
    for (int r = 0; r < 3; ++r) {
      EXPECT_NEAR(mine.translation()[r], f.p(r), 1e-9);
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(mine.linear()(r, c), f.M(r, c), 1e-12);
    }
  }
}

TEST(Puma560Test, InverseRoundTripOnRandomJoints) {
  const Puma560 arm(100.0);
  std::mt19937 rng(42);
  int checked = 0;
  for (int n = 0; n < 3000; ++n) {
    const Joints q = random_joints(rng, arm.limits());
    if (near_singular(q)) continue;
    ++checked;
    const Eigen::Isometry3d pose = arm.forward(q);
    const std::vector<Joints> solutions = arm.inverse(pose);
    ASSERT_LE(solutions.size(), 8u);
    bool found = false;
    for (const Joints& s : solutions) {
      EXPECT_TRUE(arm.limits().within(s));
      const Eigen::Isometry3d back = arm.forward(s);
      EXPECT_LT((back.translation() - pose.translation()).norm(), 1e-6) << "q=" << q.transpose();
      EXPECT_LT(rotation_error(back, pose), 1e-9);
      found = found || same_modulo_2pi(s, q, 1e-6);
    }
    EXPECT_TRUE(found) << "original q=" << q.transpose() << " not among " << solutions.size();
    const auto nearest = arm.nearest_inverse(pose, q);
    ASSERT_TRUE(nearest.has_value());
    EXPECT_LT((*nearest - q).cwiseAbs().maxCoeff(), 1e-6);
  }
  EXPECT_GT(checked, 2900);
}

TEST(Puma560Test, InverseFindsAllEightBranchesWithoutJointLimits) {
  // The PUMA's real limits cut most branches; with limits of +-2 pi every
  // branch (shoulder x elbow x wrist flip) must come out, each distinct.
  JointLimits wide = Puma560::default_limits();
  wide.q_min.setConstant(-2.0 * kPi);
  wide.q_max.setConstant(2.0 * kPi);
  const Puma560 arm(100.0, wide);
  Joints q;
  q << 0.2, 0.5, -1.2, 0.3, 0.8, 0.1;
  const auto solutions = arm.inverse(arm.forward(q));
  EXPECT_EQ(solutions.size(), 8u);
  for (std::size_t i = 0; i < solutions.size(); ++i)
    for (std::size_t j = i + 1; j < solutions.size(); ++j)
      EXPECT_FALSE(same_modulo_2pi(solutions[i], solutions[j], 1e-6)) << "duplicate solution";
}

TEST(Puma560Test, UnreachableAndNonFinitePosesGiveNoSolution) {
  const Puma560 arm;
  Eigen::Isometry3d far = Eigen::Isometry3d::Identity();
  far.translation() << 2000.0, 0.0, 0.0;
  EXPECT_TRUE(arm.inverse(far).empty());
  EXPECT_FALSE(arm.nearest_inverse(far, Joints::Zero()).has_value());
  Eigen::Isometry3d on_axis = Eigen::Isometry3d::Identity();
  on_axis.translation() << 0.0, 0.0, -300.0;  // wrist inside the d3 cylinder
  EXPECT_TRUE(arm.inverse(on_axis).empty());
  Eigen::Isometry3d nan = Eigen::Isometry3d::Identity();
  nan.translation() << std::nan(""), 0.0, 0.0;
  EXPECT_TRUE(arm.inverse(nan).empty());
}

TEST(Puma560Test, WrapIntoChoosesRepresentationNearReference) {
  EXPECT_NEAR(*wrap_into(kPi, -225 * kPi / 180, 45 * kPi / 180, 0.0), -kPi, 1e-12);
  EXPECT_NEAR(*wrap_into(-2.0, -4.6, 4.6, 4.0), -2.0 + 2 * kPi, 1e-12);  // joint 6 spans > 2 pi
  EXPECT_NEAR(*wrap_into(0.1 - 2 * kPi, -4.6, 4.6, -1.0), 0.1, 1e-12);
  EXPECT_FALSE(wrap_into(3.0, -1.0, 1.0, 0.0).has_value());
}

}  // namespace
}  // namespace ephor::arm
