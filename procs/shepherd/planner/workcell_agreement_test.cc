#include "procs/shepherd/planner/workcell_agreement.h"

#include <cmath>

#include <gtest/gtest.h>

namespace ephor::planner {
namespace {

TEST(WorkcellAgreementTest, AgreesWhileTheToolRestsOnThePlannersPlanes) {
  const geometry::Workcell cell;  // object plane 30 mm, elevation 200 mm
  WorkcellAgreement a(cell);
  EXPECT_FALSE(a.update(Plane::kElevation, 201.0));
  EXPECT_FALSE(a.update(Plane::kObject, 28.0));
  EXPECT_FALSE(a.update(std::nullopt, 120.0));  // moving: no evidence
  EXPECT_TRUE(a.agrees());
}

TEST(WorkcellAgreementTest, SaysOnceWhenTheArmUsesOtherPlaneHeightsAndOnceWhenTheyAgreeAgain) {
  const geometry::Workcell cell;
  WorkcellAgreement a(cell);
  // An arm built with a 150 mm elevation plane ends every move 50 mm low.
  const auto first = a.update(Plane::kElevation, 150.0);
  ASSERT_TRUE(first);
  EXPECT_NE(first->find("z = 150.0 mm"), std::string::npos) << *first;
  EXPECT_NE(first->find("z = 200.0 mm"), std::string::npos) << *first;
  EXPECT_FALSE(a.agrees());
  // The same report at the ARM_STATE rate is not logged again.
  for (int i = 0; i < 100; ++i) EXPECT_FALSE(a.update(Plane::kElevation, 150.0));
  EXPECT_FALSE(a.agrees());
  // Moving says nothing either way; resting at the right height ends it.
  EXPECT_FALSE(a.update(std::nullopt, 175.0));
  EXPECT_FALSE(a.agrees());
  EXPECT_TRUE(a.update(Plane::kElevation, 199.5));
  EXPECT_TRUE(a.agrees());
}

TEST(WorkcellAgreementTest, NonFiniteHeightIsNoEvidence) {
  WorkcellAgreement a(geometry::Workcell{});
  EXPECT_FALSE(a.update(Plane::kObject, std::nan("")));
  EXPECT_TRUE(a.agrees());
}

TEST(CalibrationDisagreementTest, NamesEachPlaneThatDiffers) {
  const geometry::Workcell cell;
  EXPECT_EQ(calibration_disagreement(cell, 30.4, 200.0), "");
  const std::string why = calibration_disagreement(cell, 30.0, 250.0);
  EXPECT_NE(why.find("elevation plane is at z = 250.0 mm"), std::string::npos) << why;
  EXPECT_EQ(why.find("object"), std::string::npos) << why;
}

}  // namespace
}  // namespace ephor::planner
