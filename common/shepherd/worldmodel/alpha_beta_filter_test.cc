#include "common/shepherd/worldmodel/alpha_beta_filter.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

namespace ephor::worldmodel {
namespace {

constexpr double kDt = 1.0 / 30.0;  // camera frame interval, s

TEST(AlphaBetaGainsTest, MatchKalataForAHandComputedTrackingIndex) {
  // Table 1, first filter: Lambda = 0.01 * 1^2 / 0.1 = 0.1;
  // sqrt(0.1^2 + 0.8) = 0.9, alpha = -(0.81 - 4.1 * 0.9) / 8 = 0.36,
  // beta = (0.01 + 0.4 - 0.1 * 0.9) / 4 = 0.08.
  EXPECT_DOUBLE_EQ(tracking_index(kTable1First), 0.1);
  const AlphaBetaGains g = gains_for_tracking_index(0.1);
  EXPECT_NEAR(g.alpha, 0.36, 1e-12);
  EXPECT_NEAR(g.beta, 0.08, 1e-12);
  // Kalata's identity beta^2 / (1 - alpha) = Lambda^2 holds for any Lambda.
  for (double lambda : {1e-4, 0.1, 1.0, 5.0, 40.0}) {
    const AlphaBetaGains h = gains_for_tracking_index(lambda);
    EXPECT_NEAR(h.beta * h.beta / (1.0 - h.alpha), lambda * lambda, 1e-9 * lambda * lambda);
  }
  // Second filter: Lambda = 0.05 / 0.01 = 5.
  EXPECT_DOUBLE_EQ(tracking_index(kTable1Second), 5.0);
}

TEST(AlphaBetaGainsTest, BadNoiseIsRejected) {
  EXPECT_THROW(tracking_index({0.0, 0.1, 1.0}), std::invalid_argument);
  EXPECT_THROW(tracking_index({0.01, std::nan(""), 1.0}), std::invalid_argument);
  EXPECT_THROW(gains_for_tracking_index(-1.0), std::invalid_argument);
}

TEST(AlphaBetaFilterTest, StepResponseSettlesOnTheNewPosition) {
  AlphaBetaFilter f(kTable1First);
  for (int i = 0; i < 100; ++i) {
    f.predict(kDt);
    f.update({100.0, 50.0});
  }
  ASSERT_NEAR(f.position().x(), 100.0, 1e-6);
  // Step of 10 px in x: the first correction moves alpha of the way, then it
  // settles without drifting off.
  f.predict(kDt);
  f.update({110.0, 50.0});
  EXPECT_NEAR(f.position().x(), 100.0 + 10.0 * f.gains().alpha, 1e-6);
  for (int i = 0; i < 60; ++i) {
    f.predict(kDt);
    f.update({110.0, 50.0});
  }
  EXPECT_NEAR(f.position().x(), 110.0, 0.05);
  EXPECT_NEAR(f.velocity().x(), 0.0, 0.05);
  EXPECT_NEAR(f.position().y(), 50.0, 1e-9);
}

TEST(AlphaBetaFilterTest, ConvergesToAConstantVelocityThroughNoise) {
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.2);  // px, the vision noise
  DoubleAlphaBetaFilter f;
  const Eigen::Vector2d v(8.0, -6.0);  // px/s, about a sheep's speed
  for (int i = 0; i < 300; ++i) {
    const Eigen::Vector2d truth = Eigen::Vector2d(100, 200) + v * (i * kDt);
    f.predict(kDt);
    f.update(truth + Eigen::Vector2d(noise(rng), noise(rng)));
  }
  // The smooth (second) velocity is within 0.2 px/s (2.5 %) after 10 s.
  EXPECT_NEAR(f.velocity().x(), 8.0, 0.2);
  EXPECT_NEAR(f.velocity().y(), -6.0, 0.2);
  EXPECT_NEAR(f.position().x(), 100 + 8.0 * 299 * kDt, 0.3);
  EXPECT_EQ(f.first().maneuvers(), 0);  // noise alone never trips the manoeuvre gate
}

// Frames after a 180-degree turn until the velocity's x has changed sign.
template <class Filter, class Velocity>
int frames_to_reverse(Filter& f, Velocity velocity_of) {
  const double speed = 11.0;  // px/s (30 mm/s)
  double x = 0.0;
  for (int i = 0; i < 300; ++i) {
    x += speed * kDt;
    f.predict(kDt);
    f.update({x, 0.0});
  }
  EXPECT_GT(velocity_of(f), 0.0);
  for (int k = 1; k <= 60; ++k) {
    x -= speed * kDt;
    f.predict(kDt);
    f.update({x, 0.0});
    if (velocity_of(f) < 0.0) return k;
  }
  return 1000;
}

TEST(AlphaBetaFilterTest, ATurnReversesTheVelocityWithinAFewFrames) {
  // Table 1 per step, no manoeuvre restarts: the literal paper filter.
  AlphaBetaFilter single(kTable1First);
  EXPECT_LE(frames_to_reverse(single, [](const AlphaBetaFilter& f) { return f.velocity().x(); }),
            6);
  // The default double filter: smooth, yet reverses within the paper's two
  // to three frames thanks to the manoeuvre restart.
  DoubleAlphaBetaFilter dbl;
  EXPECT_LE(frames_to_reverse(dbl, [](const DoubleAlphaBetaFilter& f) { return f.velocity().x(); }),
            3);
  EXPECT_EQ(dbl.first().maneuvers(), 1);
  // Without the restart the smooth filter takes far longer: why it exists.
  auto params = DoubleAlphaBetaFilter::Params{};
  params.maneuver_gate = 0.0;
  DoubleAlphaBetaFilter slow(params);
  EXPECT_GT(
      frames_to_reverse(slow, [](const DoubleAlphaBetaFilter& f) { return f.velocity().x(); }), 20);
}

TEST(AlphaBetaFilterTest, ASingleWildMeasurementIsHeldBackNotFollowed) {
  DoubleAlphaBetaFilter f;
  double x = 0.0;
  for (int i = 0; i < 200; ++i) {
    x += 11.0 * kDt;
    f.predict(kDt);
    f.update({x, 50.0});
  }
  x += 11.0 * kDt;
  f.predict(kDt);
  f.update({x, 55.0});  // 5 px off for one frame
  for (int i = 0; i < 10; ++i) {
    x += 11.0 * kDt;
    f.predict(kDt);
    f.update({x, 50.0});
  }
  EXPECT_EQ(f.first().maneuvers(), 0);
  EXPECT_EQ(f.first().held_back(), 1);
  EXPECT_NEAR(f.velocity().y(), 0.0, 0.05);
  EXPECT_NEAR(f.position().y(), 50.0, 0.05);
}

TEST(AlphaBetaFilterTest, NonFiniteMeasurementIsIgnored) {
  AlphaBetaFilter f(kTable1First);
  f.update({1.0, 2.0});
  EXPECT_FALSE(f.update({std::nan(""), 2.0}));
  EXPECT_EQ(f.position(), Eigen::Vector2d(1.0, 2.0));
}

}  // namespace
}  // namespace ephor::worldmodel
