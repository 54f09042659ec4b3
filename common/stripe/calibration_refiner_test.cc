#include "common/stripe/calibration_refiner.h"

#include <numbers>

#include <gtest/gtest.h>

namespace ephor::stripe {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// Seed 1 as drawn (zero references, link errors, cage) with image noise:
// section 3 by the camera, section 4's projector plane, then the joint
// refinement with the links free. The link errors are what biased the
// zero references by a few hundredths of a degree; modelled, they leave
// thousandths, and the residuals fall to the image noise.
TEST(CalibrationRefinerTest, WithLinkErrorsTheZeroReferencesComeOutExact) {
  const RobotTruth truth = RobotTruth::draw(1);
  const StripeScene table;
  const StripeWorkcell cell;
  const StripeWorld world(table, cell, truth);
  SimulatedRig rig(world, 41);
  const ZeroReferenceResult z = ZeroReferenceCalibrator(cell).calibrate(
      rig, TrueArm::nominal(), SensorCalibration::drawing_cage());
  const TrueArm zeroed = TrueArm::with_zero_offsets(z.zero_offset_rad);
  const ProjectorPlaneResult pp =
      calibrate_projector_plane(rig, cell, zeroed, z.updated, Eigen::Vector2d(0, 0));
  CalibrationRefinerOptions o;
  o.link_errors = true;
  const CalibrationRefinement r =
      CalibrationRefiner(cell, o).refine(rig, zeroed, pp.updated, z.sightings_used, z.spot_mm);
  double before = 0.0;
  for (int j = 1; j < 5; ++j) {
    const double t = truth.arm.errors().zero_offset_rad[j];
    before = std::max(before, std::abs(z.zero_offset_rad[j] - t) / kDeg);
    EXPECT_NEAR(r.zero_offset_rad[j] / kDeg, t / kDeg, 0.01) << "joint " << j + 1;  // 0.002 seen
    EXPECT_NEAR(r.correction_rad[j], r.zero_offset_rad[j] - z.zero_offset_rad[j], 1e-12);
  }
  EXPECT_GT(before, 0.02);  // the zero-reference step alone was biased
  EXPECT_LT(r.spot_rms_px, 0.05);
  EXPECT_LT(r.spot_rms_px, 0.2 * r.spot_rms_before_px);
  EXPECT_LT(r.table_rms_mm, 0.05);
  EXPECT_GT(r.stripe_views, 80u);
  EXPECT_EQ(r.arm.errors().zero_offset_rad, r.zero_offset_rad);
}

TEST(CalibrationRefinerTest, NoStripeIsAClearError) {
  const CalibrationRefiner refiner{StripeWorkcell{}};
  try {
    refiner.fit({}, {}, TrueArm::nominal(), SensorCalibration::drawing_cage(),
                Eigen::Vector2d::Zero());
    FAIL() << "expected CalibrationError";
  } catch (const CalibrationError& e) {
    EXPECT_NE(std::string(e.what()).find("only 0 stripe points"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace ephor::stripe
