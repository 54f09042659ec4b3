#include "procs/planner/field_rules.h"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

namespace ephor::planner {
namespace {

Sheep sheep(int id, double x, double y, double vx, double vy) {
  return Sheep{id, x, y, vx, vy, SheepState::kVisible};
}

TEST(FieldRulesTest, TimeToBoundaryFromPositionAndVelocity) {
  const FieldRules rules{PlannerConfig{}};
  EXPECT_NEAR(rules.time_to_boundary(sheep(1, 100, 457, -20, 0)), 5.0, 1e-12);
  EXPECT_NEAR(rules.time_to_boundary(sheep(1, 1119, 457, 20, 0)), 5.0, 1e-12);
  // Diagonal: y reaches 914 in (914 - 814) / 10 = 10 s before x reaches 1219.
  EXPECT_NEAR(rules.time_to_boundary(sheep(1, 600, 814, 10, 10)), 10.0, 1e-12);
  EXPECT_TRUE(std::isinf(rules.time_to_boundary(sheep(1, 600, 400, 0, 0))));
  EXPECT_EQ(rules.time_to_boundary(sheep(1, -5, 400, 10, 0)), 0.0);
}

TEST(FieldRulesTest, HeadingToCentreWithinTheConfiguredAngle) {
  const FieldRules rules{PlannerConfig{}};  // 0.5 rad
  EXPECT_TRUE(rules.heading_to_centre(sheep(1, 100, 457, 30, 0)));
  EXPECT_TRUE(rules.heading_to_centre(sheep(1, 100, 457, 30 * std::cos(0.4), 30 * std::sin(0.4))));
  EXPECT_FALSE(rules.heading_to_centre(sheep(1, 100, 457, 30 * std::cos(0.6), 30 * std::sin(0.6))));
  EXPECT_FALSE(rules.heading_to_centre(sheep(1, 100, 457, -30, 0)));
  EXPECT_FALSE(rules.needs_saving(sheep(1, 100, 457, 30, 0)));
  EXPECT_TRUE(rules.needs_saving(sheep(1, 100, 457, -30, 0)));
  Sheep dead = sheep(1, 100, 457, -30, 0);
  dead.state = SheepState::kDead;
  EXPECT_FALSE(rules.needs_saving(dead));
  EXPECT_FALSE(rules.needs_saving(sheep(1, 100, 457, std::numeric_limits<double>::quiet_NaN(), 0)));
}

TEST(FieldRulesTest, UsablePointsAvoidTheEdgeAndThePedestal) {
  const FieldRules rules{PlannerConfig{}};
  EXPECT_TRUE(rules.usable_point(100, 100));
  EXPECT_FALSE(rules.usable_point(5, 100));  // field margin 10 mm
  EXPECT_FALSE(rules.usable_point(1215, 100));
  EXPECT_FALSE(rules.usable_point(609.5 + 100, 457));  // within 120 mm of the pedestal axis
  EXPECT_TRUE(rules.usable_point(609.5 + 130, 457));
}

TEST(FieldRulesTest, OtherSheepNearUsesPredictedPositions) {
  const FieldRules rules{PlannerConfig{}};  // clearance 120 mm
  // Sheep 2 starts 600 mm left of (700, 200) and moves right at 30 mm/s:
  // within 120 mm from t = 16 s to t = 24 s.
  const std::vector<Sheep> all{sheep(1, 500, 500, 0, 0), sheep(2, 100, 200, 30, 0)};
  EXPECT_EQ(rules.other_sheep_near(all, 1, 700, 200, 0.0, 5.0), -1);
  EXPECT_EQ(rules.other_sheep_near(all, 1, 700, 200, 10.0, 15.9), -1);
  EXPECT_EQ(rules.other_sheep_near(all, 1, 700, 200, 10.0, 16.1), 2);
  EXPECT_EQ(rules.other_sheep_near(all, 1, 700, 200, 23.9, 30.0), 2);
  EXPECT_EQ(rules.other_sheep_near(all, 1, 700, 200, 24.1, 30.0), -1);
  // The target itself never blocks.
  EXPECT_EQ(rules.other_sheep_near(all, 2, 700, 200, 10.0, 20.0), -1);
}

}  // namespace
}  // namespace ephor::planner
