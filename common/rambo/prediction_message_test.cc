// rambo_prediction_t <-> FittedMotion: the polynomial the predictor fitted
// arrives as the same motion on the receiver's clock; bad messages are
// refused with a reason.
#include "common/rambo/prediction_message.h"

#include <gtest/gtest.h>

#include "common/rambo/pose_predictor.h"

namespace ephor::rambo {
namespace {

// A carried-target-like motion: smooth, not a constant twist.
Eigen::Isometry3d carried(double t) {
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.translation() << 900.0 + 15.0 * std::sin(0.3 * t), 20.0 * std::sin(0.2 * t + 1.0),
      100.0 + 5.0 * t;
  p.linear() = (Eigen::AngleAxisd(0.05 * t, Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(0.1 * std::sin(0.4 * t), Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  return p;
}

rambo_prediction_t fitted_message(RotationCoordinates rotation, double t_ref_s,
                                  PolynomialPosePredictor* fit) {
  std::vector<PoseSample> s;
  for (int k = 0; k <= 20; ++k) s.push_back({96.0 + 0.2 * k, carried(96.0 + 0.2 * k)});
  *fit = PolynomialPosePredictor(2, rotation);
  EXPECT_TRUE(fit->fit(s, nullptr));
  rambo_prediction_t m{};
  m.fitted = true;
  const Eigen::Isometry3d now = fit->predict(t_ref_s).pose;
  const Eigen::Quaterniond q(now.linear());
  for (int k = 0; k < 3; ++k) {
    m.position_mm[k] = now.translation()[k];
    m.principal_moments[k] = 1.0;
  }
  m.orientation_wxyz[0] = q.w();
  m.orientation_wxyz[1] = q.x();
  m.orientation_wxyz[2] = q.y();
  m.orientation_wxyz[3] = q.z();
  polynomial_to_message(fit->motion(), t_ref_s, &m);
  return m;
}

TEST(PredictionMessage, APolynomialArrivesAsTheSameMotionOnTheReceiversClock) {
  for (RotationCoordinates r :
       {RotationCoordinates::kZyxAngles, RotationCoordinates::kRotationVector}) {
    PolynomialPosePredictor fit;
    const double t_ref_s = 100.0;  // the newest pose's time on the predictor's clock
    const rambo_prediction_t m = fitted_message(r, t_ref_s, &fit);
    EXPECT_EQ(m.model, "polynomial");
    std::string why;
    // The receiver's clock has ref_utime at 1.7e9 s (the planner's wall clock).
    const auto f = motion_from_message(m, 1.7e9, &why);
    ASSERT_TRUE(f) << why;
    ASSERT_TRUE(f->polynomial);
    for (double dt : {0.0, 0.5, 1.0, 2.0}) {
      const Eigen::Isometry3d want = fit.predict(t_ref_s + dt).pose;
      const Eigen::Isometry3d got = f->pose(1.7e9 + dt);
      EXPECT_LT((want.translation() - got.translation()).norm(), 1e-6) << dt;
      EXPECT_LT(rotation_angle_between(want.linear(), got.linear()), 1e-9) << dt;
    }
  }
}

TEST(PredictionMessage, ARigidBodyMessageCarriesNoPolynomial) {
  rambo_prediction_t m{};
  m.fitted = true;
  m.orientation_wxyz[0] = 1.0;
  m.body_rates_rad_s[2] = 0.1;
  for (double& pm : m.principal_moments) pm = 1.0;
  const auto zeroed = motion_from_message(m, 5.0, nullptr);  // as an older sender's
  ASSERT_TRUE(zeroed);
  EXPECT_FALSE(zeroed->polynomial);
  no_polynomial(&m);
  const auto f = motion_from_message(m, 5.0, nullptr);
  ASSERT_TRUE(f);
  EXPECT_FALSE(f->polynomial);
  // A constant twist of 0.1 rad/s about z for 2 s.
  EXPECT_NEAR(Eigen::AngleAxisd(f->pose(7.0).linear()).angle(), 0.2, 1e-9);
}

TEST(PredictionMessage, BadMessagesAreRefusedWithAReason) {
  PolynomialPosePredictor fit;
  const rambo_prediction_t good = fitted_message(RotationCoordinates::kRotationVector, 100.0, &fit);
  std::string why;
  rambo_prediction_t m = good;
  m.fitted = false;
  m.reason = "waiting for 5 poses";
  EXPECT_FALSE(motion_from_message(m, 0.0, &why));
  EXPECT_NE(why.find("waiting"), std::string::npos) << why;
  m = good;
  m.poly_terms = 7;
  EXPECT_FALSE(motion_from_message(m, 0.0, &why));
  EXPECT_NE(why.find("7 terms"), std::string::npos) << why;
  m = good;
  m.poly_r_mid_wxyz[0] = 2.0;
  EXPECT_FALSE(motion_from_message(m, 0.0, &why));
  EXPECT_NE(why.find("unit quaternion"), std::string::npos) << why;
  m = good;
  m.poly_t_scale_s = 0.0;
  EXPECT_FALSE(motion_from_message(m, 0.0, &why));
  m = good;
  m.poly_coeff[3] = std::nan("");
  EXPECT_FALSE(motion_from_message(m, 0.0, &why));
  EXPECT_NE(why.find("not finite"), std::string::npos) << why;
}

}  // namespace
}  // namespace ephor::rambo
