#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "common/rambo/polynomial_pose_predictor.h"
#include "common/rambo/rigid_body_pose_predictor.h"
#include "common/rambo/tumbling_body.h"

namespace ephor::rambo {
namespace {

// Poses whose six coordinates (x, y, z, yaw, pitch, roll) are quadratics of t.
Eigen::Isometry3d polynomial_pose(double t) {
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.translation() << 500.0 + 40.0 * t - 6.0 * t * t, -100.0 + 25.0 * t + 3.0 * t * t,
      300.0 - 10.0 * t + 1.0 * t * t;
  p.linear() =
      from_zyx_angles(Eigen::Vector3d(0.1 + 0.5 * t + 0.1 * t * t, 0.2 - 0.1 * t + 0.02 * t * t,
                                      2.9 + 0.4 * t - 0.05 * t * t));  // roll wraps past pi
  return p;
}

TEST(PolynomialPosePredictor, RecoversNoiseFreePolynomialMotionExactly) {
  std::vector<PoseSample> s;
  for (int k = 0; k <= 30; ++k) s.push_back({k / 15.0, polynomial_pose(k / 15.0)});
  PolynomialPosePredictor p(2);
  std::string why;
  ASSERT_TRUE(p.fit(s, &why)) << why;
  for (double t : {0.5, 2.5, 3.0, 4.0}) {
    const PosePrediction pr = p.predict(t);
    const Eigen::Isometry3d truth = polynomial_pose(t);
    EXPECT_LT((pr.pose.translation() - truth.translation()).norm(), 1e-6) << t;
    EXPECT_LT(rotation_angle_between(pr.pose.linear(), truth.linear()), 1e-8) << t;
    EXPECT_LT(pr.position_sigma_mm, 1e-6);
  }
  // A goal point 200 mm out along the target's x axis, 1 s ahead.
  const Eigen::Isometry3d g(Eigen::Translation3d(200.0, 0.0, 0.0));
  EXPECT_LT(
      (p.predict_goal(g, 3.0).pose.translation() - (polynomial_pose(3.0) * g).translation()).norm(),
      1e-6);
}

TEST(PolynomialPosePredictor, RotationVectorFitRecoversAConstantTwist) {
  // A constant twist about a fixed axis through pitch = 90 deg (Euler
  // angles' singularity): linear in rotation-vector coordinates.
  const Eigen::Matrix3d r0 = from_zyx_angles(Eigen::Vector3d(0.2, 1.2, -0.3));
  const Eigen::Vector3d axis = Eigen::Vector3d(0.3, 1.0, 0.2).normalized();
  auto pose = [&](double t) {
    Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
    p.linear() = r0 * Eigen::AngleAxisd(0.8 * t, axis).toRotationMatrix();
    p.translation() << 10 * t, 0, 500;
    return p;
  };
  std::vector<PoseSample> s;
  for (int k = 0; k <= 60; ++k) s.push_back({k / 30.0, pose(k / 30.0)});
  PolynomialPosePredictor p(1, RotationCoordinates::kRotationVector);
  ASSERT_TRUE(p.fit(s, nullptr));
  EXPECT_LT(rotation_angle_between(p.predict(4.0).pose.linear(), pose(4.0).linear()), 1e-9);
}

TEST(PolynomialPosePredictor, UncertaintyGrowsWithHorizonUnderNoise) {
  std::mt19937 rng(5);
  std::normal_distribution<double> n(0.0, 1.0);
  std::vector<PoseSample> s;
  for (int k = 0; k <= 30; ++k) {
    PoseSample x{k / 15.0, polynomial_pose(k / 15.0)};
    x.pose.translation() += Eigen::Vector3d(n(rng), n(rng), n(rng));
    s.push_back(x);
  }
  PolynomialPosePredictor p(2);
  ASSERT_TRUE(p.fit(s, nullptr));
  const double s1 = p.predict(2.5).position_sigma_mm, s2 = p.predict(4.0).position_sigma_mm;
  EXPECT_GT(s1, 0.1);
  EXPECT_GT(s2, 2.0 * s1);
}

TEST(PosePredictor, BadSamplesGiveAReason) {
  PolynomialPosePredictor p(2);
  std::string why;
  EXPECT_FALSE(p.fit({{0.0, Eigen::Isometry3d::Identity()}}, &why));
  EXPECT_NE(why.find("at least 3"), std::string::npos) << why;
  std::vector<PoseSample> s{{0.0, Eigen::Isometry3d::Identity()},
                            {0.0, Eigen::Isometry3d::Identity()},
                            {0.1, Eigen::Isometry3d::Identity()}};
  EXPECT_FALSE(p.fit(s, &why));
  EXPECT_NE(why.find("not later"), std::string::npos) << why;
  s[1].t_s = 0.05;
  s[2].pose.translation().x() = std::nan("");
  EXPECT_FALSE(p.fit(s, &why));
  EXPECT_NE(why.find("not finite"), std::string::npos) << why;
  EXPECT_FALSE(p.fitted());
  EXPECT_THROW(p.predict(0.0), std::logic_error);
  EXPECT_THROW(RigidBodyPosePredictor(Eigen::Vector3d(1.0, 1.0, 3.0)), std::invalid_argument);
}

// A box-like target spinning near its intermediate axis: it tumbles (the
// twist is not constant), while its angular momentum stays fixed.
TumblingBody make_tumbler() {
  Eigen::Isometry3d p0 = Eigen::Isometry3d::Identity();
  p0.translation() << 600.0, 0.0, 300.0;
  p0.linear() = from_zyx_angles(Eigen::Vector3d(0.3, -0.2, 0.5));
  return TumblingBody(p0, Eigen::Vector3d(40.0, -20.0, 10.0), Eigen::Vector3d(0.15, 1.0, 0.25),
                      Eigen::Vector3d(1.0, 2.0, 3.0));
}

TEST(TumblingBody, ConservesAngularMomentumAndEnergy) {
  TumblingBody b = make_tumbler();
  const Eigen::Vector3d m(1.0, 2.0, 3.0);
  const auto momentum = [&](double t) {
    return (b.pose(t).linear() * m.cwiseProduct(b.body_rates(t))).eval();
  };
  const Eigen::Vector3d l0 = momentum(0.0);
  const double e0 = b.body_rates(0.0).dot(m.cwiseProduct(b.body_rates(0.0)));
  const Eigen::Vector3d l1 = momentum(10.0);
  const double e1 = b.body_rates(10.0).dot(m.cwiseProduct(b.body_rates(10.0)));
  EXPECT_LT((l1 - l0).norm(), 1e-9 * l0.norm());
  EXPECT_NEAR(e1, e0, 1e-9 * e0);
  // ... while the body rates change a lot (a tumble, not a constant twist).
  EXPECT_GT((b.body_rates(4.0) - b.body_rates(0.0)).norm(), 0.3);
}

std::vector<PoseSample> observe(TumblingBody& b, double t0, double t1, double hz, double noise_mm,
                                double noise_rad, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0.0, 1.0);
  std::vector<PoseSample> s;
  for (double t = t0; t <= t1 + 1e-9; t += 1.0 / hz) {
    PoseSample x{t, b.pose(t)};
    x.pose.translation() += noise_mm * Eigen::Vector3d(n(rng), n(rng), n(rng));
    const Eigen::Vector3d e = noise_rad * Eigen::Vector3d(n(rng), n(rng), n(rng));
    if (e.norm() > 0)
      x.pose.linear() =
          x.pose.linear() * Eigen::AngleAxisd(e.norm(), e.normalized()).toRotationMatrix();
    s.push_back(x);
  }
  return s;
}

TEST(RigidBodyPosePredictor, RecoversNoiseFreeTumble) {
  TumblingBody b = make_tumbler();
  auto s = observe(b, 0.0, 2.0, 30.0, 0.0, 0.0, 1);
  RigidBodyPosePredictor p(Eigen::Vector3d(1.0, 2.0, 3.0));
  std::string why;
  ASSERT_TRUE(p.fit(s, &why)) << why;
  const Eigen::Isometry3d g(Eigen::Translation3d(150.0, 100.0, 0.0));
  const double t = s.back().t_s + 2.0;
  const double err =
      (p.predict_goal(g, t).pose.translation() - (b.pose(t) * g).translation()).norm();
  EXPECT_LT(err, 0.05);  // mm, 2 s ahead (RK4 at 5 ms against 0.5 ms truth)
  EXPECT_LT((p.body_rates_rad_s() - b.body_rates(s.back().t_s)).norm(), 1e-5);
}

// A span far beyond any horizon (a prediction stamped 1700 years ahead,
// fuzz target rambo_planner) is cut to kMaxSteps steps: the state there, a
// unit quaternion; a non-finite span leaves the state as it is.
TEST(RigidBodyPosePredictor, PropagationOverAHugeSpanIsBounded) {
  const Eigen::Vector3d m(1.0, 2.0, 3.0);
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  Eigen::Vector3d w(0.1, 0.2, 0.05);
  RigidBodyPosePredictor::propagate(m, 0.005, -5.2635820644892672e10, &q, &w);
  EXPECT_NEAR(q.norm(), 1.0, 1e-9);
  EXPECT_TRUE(w.allFinite());
  Eigen::Quaterniond q_cut = Eigen::Quaterniond::Identity();
  Eigen::Vector3d w_cut(0.1, 0.2, 0.05);
  RigidBodyPosePredictor::propagate(m, 0.005, -0.005 * RigidBodyPosePredictor::kMaxSteps, &q_cut,
                                    &w_cut);
  EXPECT_LT((q.coeffs() - q_cut.coeffs()).norm(), 1e-12);
  Eigen::Quaterniond q2 = Eigen::Quaterniond::Identity();
  Eigen::Vector3d w2(0.1, 0.2, 0.05);
  RigidBodyPosePredictor::propagate(m, 0.005, std::nan(""), &q2, &w2);
  EXPECT_EQ(q2.coeffs(), Eigen::Quaterniond::Identity().coeffs());
  EXPECT_EQ(w2, Eigen::Vector3d(0.1, 0.2, 0.05));
}

// With noise (0.5 mm, 0.2 deg per axis at 30 Hz over 2 s), 2 s ahead: the
// rigid-body model predicts a goal point 180 mm from the centre far better
// than the paper's quadratic fits.
TEST(RigidBodyPosePredictor, BeatsPolynomialOnTumblingBodyAtTwoSeconds) {
  double err_poly = 0.0, err_rigid = 0.0;
  const Eigen::Isometry3d g(Eigen::Translation3d(150.0, 100.0, 0.0));
  for (unsigned seed = 1; seed <= 3; ++seed) {
    TumblingBody b = make_tumbler();
    const double t_start = 1.0 * seed;
    auto s = observe(b, t_start, t_start + 2.0, 30.0, 0.5, 0.2 * M_PI / 180.0, seed);
    PolynomialPosePredictor poly(2);
    RigidBodyPosePredictor rigid(Eigen::Vector3d(1.0, 2.0, 3.0));
    ASSERT_TRUE(poly.fit(s, nullptr));
    ASSERT_TRUE(rigid.fit(s, nullptr));
    const double t = s.back().t_s + 2.0;
    const Eigen::Vector3d truth = (b.pose(t) * g).translation();
    err_poly += (poly.predict_goal(g, t).pose.translation() - truth).norm() / 3.0;
    const PosePrediction pr = rigid.predict_goal(g, t);
    err_rigid += (pr.pose.translation() - truth).norm() / 3.0;
    EXPECT_GT(pr.position_sigma_mm, 0.0);
  }
  EXPECT_LT(err_rigid, 10.0);             // mm
  EXPECT_LT(err_rigid, 0.25 * err_poly);  // at least 4 times better
  RecordProperty("err_poly_mm", std::to_string(err_poly));
  RecordProperty("err_rigid_mm", std::to_string(err_rigid));
  std::printf("2 s horizon, goal point error: polynomial %.1f mm, rigid body %.2f mm\n", err_poly,
              err_rigid);
}

}  // namespace
}  // namespace ephor::rambo
