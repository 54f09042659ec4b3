#include "common/stripe/zero_reference_calibrator.h"

#include <numbers>

#include <gtest/gtest.h>

namespace ephor::stripe {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// The camera's true pose on the flange as the software can know it: the
// true C_T turned by joint 6's zero-reference error (which no camera
// measurement tells apart from the cage's turn about z6).
Eigen::Isometry3d camera_with_joint6(const RobotTruth& truth) {
  return Eigen::Isometry3d(
             Eigen::AngleAxisd(truth.arm.errors().zero_offset_rad[5], Eigen::Vector3d::UnitZ())) *
         truth.cage.camera_in_flange;
}

// A rig whose camera never sees the spot.
class BlindRig : public CalibrationRig {
 public:
  cv::Mat stripe_image(const arm::Joints&) override { return blank(); }
  cv::Mat spot_image(const arm::Joints&) override { return blank(); }

 private:
  static cv::Mat blank() { return cv::Mat(256, 256, CV_8UC1, cv::Scalar(170)); }
};

// Seed 2's zero references (up to 1 deg on joints 2-6) and cage (3 mm,
// 2 deg off the drawing), links exact, no image noise: the fit recovers
// joints 2-5 and the camera's pose (joint 6 folded in) to the spot
// centroid's accuracy.
TEST(ZeroReferenceCalibratorTest, RecoversZeroReferencesOnANoiseFreeArm) {
  RobotTruth truth = RobotTruth::draw(2);
  ArmErrors e = truth.arm.errors();
  e.dh_error = {};
  truth.arm = TrueArm(e);
  StripeRendererOptions o;
  o.noise_sigma_grey = 0.0;
  const StripeScene table;
  const StripeWorld world(table, StripeWorkcell{}, truth, o);
  SimulatedRig rig(world, 11);
  const ZeroReferenceCalibrator cal{StripeWorkcell{}};
  const SensorCalibration drawing = SensorCalibration::drawing_cage();
  const ZeroReferenceResult r = cal.calibrate(rig, TrueArm::nominal(), drawing);

  EXPECT_GT(r.sightings, 100u);
  EXPECT_GT(r.lefty_sightings, 20);
  EXPECT_LT(r.rms_px, 0.03);  // 0.009 px seen
  EXPECT_LT(r.max_px, 0.06);
  double largest = 0.0;
  for (int j = 1; j < 5; ++j) {
    largest = std::max(largest, std::abs(e.zero_offset_rad[j]));
    EXPECT_NEAR(r.zero_offset_rad[j] / kDeg, e.zero_offset_rad[j] / kDeg, 0.003)
        << "joint " << j + 1;
    EXPECT_NEAR(r.correction_rad[j], r.zero_offset_rad[j], 1e-12);
  }
  EXPECT_GT(largest, 0.3 * kDeg);  // the errors were there to find
  EXPECT_EQ(r.zero_offset_rad[0], 0.0);
  EXPECT_EQ(r.zero_offset_rad[5], 0.0);  // into C_T instead
  const Eigen::Isometry3d want = camera_with_joint6(truth);
  const Eigen::Isometry3d& got = r.updated.camera_in_flange;
  EXPECT_LT((got.translation() - want.translation()).norm(), 0.05);
  EXPECT_LT(Eigen::AngleAxisd(got.linear().transpose() * want.linear()).angle() / kDeg, 0.003);
  EXPECT_LT((r.spot_mm - Eigen::Vector2d::Zero()).norm(), 0.02);
  // The paper's symptom: righty and lefty put the spot in different places
  // under the nominal model (34 mm here), in the same place after (up to
  // the ~0.05 mm the spot's centroid is off its centre's image on tilted
  // views, which this diagnostic does not correct).
  EXPECT_GT(r.lefty_righty_gap_before_mm, 10.0);
  EXPECT_LT(r.lefty_righty_gap_after_mm, 0.1);
}

// Image noise and the link errors no calibration here models (seed 1):
// the zero references come out near the truth, biased by what the link
// errors (+-0.3 mm, +-0.05 deg) look like to the fit (0.02-0.04 deg seen).
TEST(ZeroReferenceCalibratorTest, NoiseAndLinkErrorsLeaveASmallBias) {
  const RobotTruth truth = RobotTruth::draw(1);
  const StripeScene table;
  const StripeWorld world(table, StripeWorkcell{}, truth);
  SimulatedRig rig(world, 21);
  const ZeroReferenceCalibrator cal{StripeWorkcell{}};
  const ZeroReferenceResult r =
      cal.calibrate(rig, TrueArm::nominal(), SensorCalibration::drawing_cage());
  for (int j = 1; j < 5; ++j)
    EXPECT_NEAR(r.zero_offset_rad[j] / kDeg, truth.arm.errors().zero_offset_rad[j] / kDeg, 0.1)
        << "joint " << j + 1;
  EXPECT_LT(r.lefty_righty_gap_after_mm, 0.2 * r.lefty_righty_gap_before_mm);
}

// Image noise alone (seed 3's zero references and cage, links exact):
// what the sightings' noise leaves on the joints, apart from link errors.
TEST(ZeroReferenceCalibratorTest, ImageNoiseAloneLeavesThousandthsOfADegree) {
  RobotTruth truth = RobotTruth::draw(3);
  ArmErrors e = truth.arm.errors();
  e.dh_error = {};
  truth.arm = TrueArm(e);
  const StripeScene table;
  const StripeWorld world(table, StripeWorkcell{}, truth);
  SimulatedRig rig(world, 31);
  const ZeroReferenceCalibrator cal{StripeWorkcell{}};
  const ZeroReferenceResult r =
      cal.calibrate(rig, TrueArm::nominal(), SensorCalibration::drawing_cage());
  for (int j = 1; j < 5; ++j)
    EXPECT_NEAR(r.zero_offset_rad[j] / kDeg, e.zero_offset_rad[j] / kDeg, 0.002)  // 0.0002 seen
        << "joint " << j + 1;
}

TEST(ZeroReferenceCalibratorTest, NoSpotIsAClearError) {
  BlindRig rig;
  const ZeroReferenceCalibrator cal{StripeWorkcell{}};
  try {
    cal.calibrate(rig, TrueArm::nominal(), SensorCalibration::drawing_cage());
    FAIL() << "expected CalibrationError";
  } catch (const CalibrationError& e) {
    EXPECT_NE(std::string(e.what()).find("spot was seen in only 0 views"), std::string::npos)
        << e.what();
  }
}

TEST(ZeroReferenceCalibratorTest, PlansRightyAndLeftyBranchesClearOfTheTable) {
  const ZeroReferenceCalibrator cal{StripeWorkcell{}};
  const auto plan =
      cal.plan(TrueArm::nominal(), SensorCalibration::drawing_cage(), Eigen::Vector2d::Zero());
  int lefty = 0;
  for (const auto& q : plan) lefty += std::cos(q[1]) > 0.0 ? 1 : 0;
  EXPECT_GT(lefty, 10);
  EXPECT_GT(static_cast<int>(plan.size()) - lefty, 10);
}

}  // namespace
}  // namespace ephor::stripe
