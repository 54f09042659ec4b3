#include "procs/shepherd/planner/bounce_predictor.h"

#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

namespace ephor::planner {
namespace {

// The default work cell: a 1219 x 914 mm field, the pedestal (radius 70 mm)
// at its centre (609.5, 457).
BouncePredictorConfig config() { return BouncePredictorConfig{}; }

TEST(BouncePredictorTest, AloneOnTheFieldASheepLeavesAlongItsStraightLine) {
  const BouncePredictor p(config());
  // 200 mm from the right edge at 10 mm/s, away from the pedestal's line.
  const auto t = p.exit_times_s({Sheep{1, 1019, 150, 10, 0, SheepState::kVisible}});
  ASSERT_EQ(t.size(), 1u);
  EXPECT_NEAR(t[0], 20.0, 0.11);
}

TEST(BouncePredictorTest, ASheepWalkingIntoThePedestalComesBackOut) {
  BouncePredictorConfig c = config();
  c.horizon_s = 60.0;
  const BouncePredictor p(c);
  // 400 mm left of the column's centre, walking at it at 20 mm/s: contact
  // when its nose (114.5 mm) meets the column (70 mm), 215.5 mm on (10.8 s),
  // then back out over the left edge, 209.5 + 215.5 mm... 424.5 mm later.
  const std::vector<Sheep> s{Sheep{1, 209.5, 457, 20, 0, SheepState::kVisible}};
  const auto t = p.exit_times_s(s);
  EXPECT_NEAR(t[0], (215.5 + 424.5) / 20.0, 0.3);
  // Without the pedestal it crosses the field: 1009.5 mm to the right edge.
  c.pedestal = false;
  EXPECT_NEAR(BouncePredictor(c).exit_times_s(s)[0], 1009.5 / 20.0, 0.3);
}

TEST(BouncePredictorTest, ASheepWalkingOutIsTurnedBackByAnotherWalkingAcross) {
  BouncePredictorConfig c = config();
  c.horizon_s = 60.0;
  c.pedestal = false;
  const BouncePredictor p(c);
  // Sheep 1 heads down to the bottom edge (y = 0), 300 mm away; sheep 2
  // comes up at it head-on from below. They meet nose to nose and sheep 1
  // is sent back up: it leaves over the top edge much later, if at all in
  // the horizon, instead of in 30 s.
  const std::vector<Sheep> s{Sheep{1, 300, 300, 0, -10, SheepState::kVisible},
                             Sheep{2, 300, 20 + 5, 0, 10, SheepState::kVisible}};
  const auto t = p.exit_times_s(s);
  EXPECT_GT(t[0], 40.0);
  c.sheep = false;
  EXPECT_NEAR(BouncePredictor(c).exit_times_s(s)[0], 30.0, 0.11);
}

TEST(BouncePredictorTest, DeadStandingAndNonFiniteSheepNeverLeaveOutsideOnesHaveLeft) {
  const BouncePredictor p(config());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const auto t = p.exit_times_s({Sheep{1, 300, 300, 10, 0, SheepState::kDead},
                                 Sheep{2, 300, 300, 0.5, 0, SheepState::kVisible},
                                 Sheep{3, nan, 300, 10, 0, SheepState::kVisible},
                                 Sheep{4, -5, 300, -10, 0, SheepState::kVisible}});
  EXPECT_TRUE(std::isinf(t[0]));
  EXPECT_TRUE(std::isinf(t[1]));
  EXPECT_TRUE(std::isinf(t[2]));
  EXPECT_EQ(t[3], 0.0);
}

}  // namespace
}  // namespace ephor::planner
