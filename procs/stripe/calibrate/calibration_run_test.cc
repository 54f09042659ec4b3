// The calibrate process's procedure on the simulated rig (no bus): the quick
// views from the drawing on a seeded bad robot recover the zero references
// and the cage well enough for scans within the targets.

#include "procs/stripe/calibrate/calibration_run.h"

#include <cstdio>
#include <numbers>

#include <gtest/gtest.h>

#include "common/stripe/direction_error.h"
#include "common/stripe/stripe_world.h"

namespace ephor::stripe {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

TEST(CalibrationRun, QuickViewsRecoverTheZeroReferencesOfASeededArm) {
  const StripeScene table;
  const StripeWorkcell cell;
  const RobotTruth truth = RobotTruth::draw(2);
  const StripeWorld world(table, cell, truth);
  SimulatedRig rig(world, 77);
  CalibrationRunOptions o;
  o.views = CalibrationViews::kQuick;
  std::vector<std::string> lines;
  const CalibrationRunResult r = run_calibration(rig, cell, StripeCalibration::drawing(2), o,
                                                 [&](const std::string& l) { lines.push_back(l); });
  EXPECT_EQ(lines.size(), 5u);
  EXPECT_EQ(r.calibration.report, lines);
  EXPECT_EQ(r.calibration.robot_seed, 2);
  EXPECT_LT(r.views, 50);
  for (int j = 1; j < 5; ++j) {
    EXPECT_NEAR(r.calibration.arm.zero_offset_rad[j] / kDeg,
                truth.arm.errors().zero_offset_rad[j] / kDeg, 0.03)
        << "joint " << j + 1;
  }
  // What the calibration is for (section 5): the pyramid's apex located
  // from 20 directions stays put (the nominal model: 26 mm on this robot).
  const StripeScene pyramid = StripeScene::load(std::string(EPHOR_STRIPE_SCENES) + "/pyramid.obj");
  const StripeWorld scene(pyramid, cell, truth);
  const RangeFinder finder(cell, r.calibration.arm_model(), r.calibration.sensor);
  const DirectionError e =
      measure_direction_error(scene, finder, section5_views(), Eigen::Vector3d(0, 0, 60), 5);
  std::printf("direction-dependent error after the quick calibration: %.3f mm (%d views)\n",
              e.worst_from_mean_mm, e.located);
  EXPECT_EQ(e.located, 20);
  EXPECT_LT(e.worst_from_mean_mm, 1.0);
  EXPECT_LT(r.refinement.table_rms_mm, 0.1);
}

TEST(CalibrationRun, ViewsPresetsParse) {
  EXPECT_EQ(parse_calibration_views("full"), CalibrationViews::kFull);
  EXPECT_EQ(parse_calibration_views("quick"), CalibrationViews::kQuick);
  EXPECT_THROW(parse_calibration_views("fast"), std::invalid_argument);
  CalibrationRunOptions o;
  EXPECT_TRUE(zero_reference_options(o).working_branch_only);
  o.all_branches = true;
  EXPECT_FALSE(zero_reference_options(o).working_branch_only);
}

}  // namespace
}  // namespace ephor::stripe
