#include "common/catch/worldmodel/exit_spread.h"

#include <cmath>

#include <gtest/gtest.h>

namespace ephor::catching {
namespace {

class ExitSpreadTest : public ::testing::Test {
 protected:
  BoardSpec board_;
  BoardPlacement placement_;
};

TEST_F(ExitSpreadTest, ACertainStateGivesOneExitCoveredWhole) {
  const ExitPredictor predictor(board_, placement_);
  const Eigen::Vector4d state(200.0, 300.0, 150.0, 800.0);
  const ExitPrediction single = predictor.predict(state, Eigen::Matrix4d::Zero());
  const ExitSpreadResult r =
      ExitSpread(predictor, {16, 0.0, 30.0, 1}).sample(state, Eigen::Matrix4d::Zero());
  ASSERT_TRUE(r.ok);
  EXPECT_EQ(r.samples, 16);
  EXPECT_EQ(r.exits.size(), 16u);
  EXPECT_DOUBLE_EQ(r.cover_fraction, 1.0);
  EXPECT_NEAR(r.cover_exit_x_b_mm, single.exit_x_b_mm, 1e-9);
  EXPECT_LT((r.cover_point_w_mm - single.catch_point_w_mm).norm(), 1e-9);
  EXPECT_NEAR(r.cover_time_to_catch_s, single.time_to_catch_s, 1e-12);
  EXPECT_NEAR(r.exit_x_sd_mm, 0.0, 1e-6);
}

// Without pegs the exit is nearly linear in the state: the samples' spread
// matches the first-order sigma of ExitPredictor.
TEST_F(ExitSpreadTest, WithoutPegsTheSpreadMatchesTheLinearisedSigma) {
  const ExitPredictor predictor(board_, placement_);
  const Eigen::Vector4d state(300.0, 300.0, 20.0, 600.0);
  Eigen::Matrix4d cov = Eigen::Matrix4d::Zero();
  cov.diagonal() << 4.0, 4.0, 400.0, 400.0;  // 2 mm, 20 mm/s
  const ExitPrediction single = predictor.predict(state, cov);
  const ExitSpreadResult r = ExitSpread(predictor, {400, 0.0, 30.0, 7}).sample(state, cov);
  ASSERT_TRUE(r.ok);
  EXPECT_NEAR(r.exit_x_sd_mm, single.sigma_exit_x_mm, 0.1 * single.sigma_exit_x_mm);
  // 10th to 90th percentile: 2.56 sigma of a normal distribution.
  EXPECT_NEAR(r.exit_x_p90_mm - r.exit_x_p10_mm, 2.56 * single.sigma_exit_x_mm,
              0.15 * 2.56 * single.sigma_exit_x_mm);
  // The exit x of the cover lies near the mean, the cup covering most samples.
  EXPECT_NEAR(r.cover_exit_x_b_mm, single.exit_x_b_mm, 0.3 * single.sigma_exit_x_mm);
  EXPECT_GT(r.cover_fraction, 0.9);  // sigma ~ 10 mm against a 30 mm radius
}

// A ball rolling straight at a peg with 3 mm of uncertainty across its path
// passes it on either side: the exits split into two clusters far apart
// (measured: 26-177 mm and 227-579 mm, most near the rails, of 64). The
// cover takes part of one cluster, not the empty middle under the peg; the
// spread shows both.
TEST_F(ExitSpreadTest, APegAheadSplitsTheExitsAndTheCoverTakesOneSide) {
  ExitPredictor predictor(board_, placement_);
  predictor.set_pegs({Eigen::Vector2d(300.0, 400.0)}, 6.0);
  const Eigen::Vector4d state(300.0, 100.0, 0.0, 300.0);
  Eigen::Matrix4d cov = Eigen::Matrix4d::Zero();
  cov(0, 0) = 9.0;
  const ExitSpreadResult r = ExitSpread(predictor, {64, 0.5, 30.0, 3}).sample(state, cov);
  ASSERT_TRUE(r.ok);
  EXPECT_LT(r.exit_x_p10_mm, 150.0);
  EXPECT_GT(r.exit_x_p90_mm, 450.0);
  EXPECT_GT(r.cover_fraction, 0.15);
  EXPECT_LT(r.cover_fraction, 0.6);
  EXPECT_GT(std::abs(r.cover_exit_x_b_mm - 300.0), 150.0);
  // Every covered sample lies within the capture radius of the cover point.
  int covered = 0;
  for (const ExitSample& e : r.exits)
    covered += (e.catch_point_w_mm.head<2>() - r.cover_point_w_mm.head<2>()).norm() <= 30.0;
  EXPECT_EQ(covered, static_cast<int>(std::lround(r.cover_fraction * r.samples)));
}

TEST_F(ExitSpreadTest, TheSameInputGivesTheSameSpread) {
  ExitPredictor predictor(board_, placement_);
  predictor.set_pegs({Eigen::Vector2d(300.0, 400.0), Eigen::Vector2d(250.0, 600.0)}, 6.0);
  const Eigen::Vector4d state(305.0, 150.0, -10.0, 400.0);
  const Eigen::Matrix4d cov = Eigen::Matrix4d::Identity() * 25.0;
  const ExitSpread spread(predictor);
  const ExitSpreadResult a = spread.sample(state, cov), b = spread.sample(state, cov);
  ASSERT_EQ(a.exits.size(), b.exits.size());
  for (size_t i = 0; i < a.exits.size(); ++i)
    EXPECT_EQ(a.exits[i].exit_x_b_mm, b.exits[i].exit_x_b_mm);
  EXPECT_EQ(a.cover_point_w_mm, b.cover_point_w_mm);
}

TEST_F(ExitSpreadTest, BadInputIsRefusedOrNotOk) {
  const ExitPredictor predictor(board_, placement_);
  EXPECT_THROW(ExitSpread(predictor, {0, 0.5, 30.0, 1}), std::invalid_argument);
  EXPECT_THROW(ExitSpread(predictor, {8, -1.0, 30.0, 1}), std::invalid_argument);
  EXPECT_THROW(ExitSpread(predictor, {8, 0.5, 0.0, 1}), std::invalid_argument);
  const ExitSpread spread(predictor);
  EXPECT_FALSE(spread.sample(Eigen::Vector4d(std::nan(""), 1, 1, 1), Eigen::Matrix4d::Zero()).ok);
  Eigen::Matrix4d bad = Eigen::Matrix4d::Identity();
  bad(1, 1) = std::nan("");
  EXPECT_FALSE(spread.sample(Eigen::Vector4d(300, 100, 0, 300), bad).ok);
  // An indefinite covariance (rounding) is clipped, not a crash.
  Eigen::Matrix4d indefinite = Eigen::Matrix4d::Identity();
  indefinite(2, 2) = -1e-9;
  EXPECT_TRUE(spread.sample(Eigen::Vector4d(300, 100, 0, 300), indefinite).ok);
}

}  // namespace
}  // namespace ephor::catching
