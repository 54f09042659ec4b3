#include "common/catch/worldmodel/ball_kalman_filter.h"

#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>
#include <Eigen/Eigenvalues>

#include "common/catch/worldmodel/test_scene.h"

namespace ephor::catching {
namespace {

constexpr double kFrame = 1.0 / 60.0;
constexpr double kNoise = 1.0;  // mm per axis

BallKalmanParams params_for(const BoardPlacement& placement) {
  BallKalmanParams p;
  p.acceleration_mm_s2 = testing::rolling_acceleration(placement);
  return p;
}

struct FilterRun {
  double worst_velocity_error_after_03 = 0.0;  // mm/s, from t = 0.3 s on
  double worst_position_error_after_03 = 0.0;  // mm
  double recovered_after_s =
      -1.0;  // after the bounce: first time the velocity error stays < 50 mm/s
  int bounces = 0;
};

FilterRun run_filter(const BallKalmanParams& params,
                     const std::vector<testing::RollingSample>& track, double bounce_t = -1.0) {
  BallKalmanFilter kf(params);
  const Eigen::Matrix2d r = Eigen::Matrix2d::Identity() * kNoise * kNoise;
  FilterRun run;
  double last_bad = bounce_t;
  for (std::size_t k = 0; k < track.size(); ++k) {
    const auto& s = track[k];
    if (k == 0) {
      kf.initialise(s.measured_mm, r);
      continue;
    }
    kf.predict(s.t_s - track[k - 1].t_s);
    kf.update(s.measured_mm, r);
    const double ev = (kf.velocity() - s.velocity_mm_s).norm();
    const double ep = (kf.position() - s.position_mm).norm();
    if (s.t_s >= 0.3 - 1e-9 && (bounce_t < 0.0 || s.t_s < bounce_t)) {
      run.worst_velocity_error_after_03 = std::max(run.worst_velocity_error_after_03, ev);
      run.worst_position_error_after_03 = std::max(run.worst_position_error_after_03, ep);
    }
    if (bounce_t >= 0.0 && s.t_s >= bounce_t && ev >= 50.0) last_bad = s.t_s;
  }
  if (bounce_t >= 0.0) run.recovered_after_s = last_bad - bounce_t + kFrame;
  run.bounces = kf.bounces();
  return run;
}

TEST(BallKalmanFilterTest, ConvergesOnARollingBall) {
  const BoardSpec board;
  const BoardPlacement placement;
  const BallKalmanParams params = params_for(placement);
  for (unsigned seed = 1; seed <= 10; ++seed) {
    const auto track = testing::simulate_roll(board, params.acceleration_mm_s2, {200.0, 30.0},
                                              {120.0, 50.0}, kFrame, kNoise, seed);
    const FilterRun run = run_filter(params, track);
    std::printf(
        "seed %u: worst velocity error after 0.3 s %.1f mm/s, position %.2f mm, bounces %d\n", seed,
        run.worst_velocity_error_after_03, run.worst_position_error_after_03, run.bounces);
    EXPECT_LT(run.worst_velocity_error_after_03, 20.0) << "seed " << seed;
    EXPECT_LT(run.worst_position_error_after_03, 2.0) << "seed " << seed;
    EXPECT_EQ(run.bounces, 0) << "seed " << seed;  // no false bounce on a clean track
  }
}

TEST(BallKalmanFilterTest, RecoversFromAPegBounceWithinATenthOfASecond) {
  const BoardSpec board;
  const BoardPlacement placement;
  const BallKalmanParams params = params_for(placement);
  BallKalmanParams no_inflation = params;
  no_inflation.bounce_nis_threshold = 0.0;
  const double bounce_t = 0.4 + 0.5 * kFrame;  // between two frames
  for (unsigned seed = 1; seed <= 10; ++seed) {
    // At 0.4 s the ball (~1.2 m/s down) hits a peg: thrown sideways and
    // slowed to a fifth down the slope.
    const auto track =
        testing::simulate_roll(board, params.acceleration_mm_s2, {200.0, 30.0}, {120.0, 50.0},
                               kFrame, kNoise, seed, {{bounce_t, Eigen::Vector2d(-700.0, 250.0)}});
    const FilterRun run = run_filter(params, track, bounce_t);
    const FilterRun plain = run_filter(no_inflation, track, bounce_t);
    std::printf(
        "seed %u: recovered (< 50 mm/s) %.3f s after the bounce (%.3f s without inflation), "
        "bounces %d\n",
        seed, run.recovered_after_s, plain.recovered_after_s, run.bounces);
    EXPECT_LE(run.recovered_after_s, 0.1) << "seed " << seed;
    EXPECT_GE(run.bounces, 1);
    EXPECT_GT(plain.recovered_after_s, run.recovered_after_s);
  }
}

TEST(BallKalmanFilterTest, PredictMatchesTheRollingKinematicsAndCovarianceStaysValid) {
  BallKalmanParams params;
  params.acceleration_mm_s2 = 3000.0;
  params.accel_sigma_x_mm_s2 = 0.0;
  params.accel_sigma_y_mm_s2 = 0.0;
  BallKalmanFilter kf(params);
  kf.initialise({100.0, 200.0}, Eigen::Matrix2d::Identity(), {50.0, 400.0});
  kf.predict(0.2);
  EXPECT_NEAR(kf.position().x(), 110.0, 1e-9);
  EXPECT_NEAR(kf.position().y(), 200.0 + 80.0 + 0.5 * 3000.0 * 0.04, 1e-9);
  EXPECT_NEAR(kf.velocity().y(), 400.0 + 600.0, 1e-9);
  // Position variance grew by T^2 sigma_v^2.
  const double sv = params.initial_velocity_sigma_mm_s;
  EXPECT_NEAR(kf.covariance()(0, 0), 1.0 + 0.04 * sv * sv, 1e-6);
  kf.update({111.0, 340.0}, Eigen::Matrix2d::Identity());
  const BallKalmanFilter::Covariance p = kf.covariance();
  EXPECT_LT((p - p.transpose()).norm(), 1e-9);
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d>(p).eigenvalues().minCoeff(), 0.0);
  // Non-finite input changes nothing.
  const auto before = kf.state();
  EXPECT_FALSE(kf.update({std::nan(""), 0.0}, Eigen::Matrix2d::Identity()).applied);
  EXPECT_EQ(kf.state(), before);
}

TEST(BallKalmanFilterTest, PredictBouncesTheBallOffAKnownPeg) {
  const BoardPlacement placement;
  BallKalmanFilter filter(params_for(placement));
  filter.set_pegs({Eigen::Vector2d(290.0, 300.0)}, 26.0);  // 6 mm peg + 20 mm ball
  // Straight down the slope at 1 m/s towards a peg 10 mm to its left.
  filter.initialise({300.0, 250.0}, Eigen::Matrix2d::Identity(), Eigen::Vector2d(0.0, 1000.0));
  for (int i = 0; i < 6; ++i) filter.predict(1.0 / 60.0);
  EXPECT_EQ(filter.peg_bounces(), 1);
  EXPECT_GT(filter.velocity().x(), 100.0);  // deflected to the right
  EXPECT_GE((filter.position() - Eigen::Vector2d(290.0, 300.0)).norm(), 26.0 - 1e-9);
  // The covariance stays symmetric and positive definite.
  const Eigen::Matrix4d p = filter.covariance();
  EXPECT_LT((p - p.transpose()).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d>(p).eigenvalues().minCoeff(), 0.0);

  // Without the peg the ball rolls straight on.
  BallKalmanFilter free(params_for(placement));
  free.initialise({300.0, 250.0}, Eigen::Matrix2d::Identity(), Eigen::Vector2d(0.0, 1000.0));
  for (int i = 0; i < 6; ++i) free.predict(1.0 / 60.0);
  EXPECT_EQ(free.velocity().x(), 0.0);
  EXPECT_THROW(free.set_pegs({Eigen::Vector2d(1.0, 1.0)}, 0.0), std::invalid_argument);
}

// The velocity variance a modelled bounce adds: none with a perfectly known
// peg and restitution and a certain position; more for a grazing contact
// than for a head-on one (the outgoing direction of a graze is nearly
// unknown).
TEST(BallKalmanFilterTest, AModelledBounceAddsVelocityUncertaintyMostWhenGrazing) {
  const BoardPlacement placement;
  const auto added_velocity_variance = [&](double offset_mm, const BallKalmanParams& params) {
    BallKalmanFilter filter(params);
    filter.set_pegs({Eigen::Vector2d(300.0 - offset_mm, 300.0)}, 26.0);
    filter.initialise({300.0, 250.0}, Eigen::Matrix2d::Identity() * 1e-6,
                      Eigen::Vector2d(0.0, 1000.0));
    BallKalmanFilter free(params);
    free.initialise({300.0, 250.0}, Eigen::Matrix2d::Identity() * 1e-6,
                    Eigen::Vector2d(0.0, 1000.0));
    for (int i = 0; i < 6; ++i) {
      filter.predict(1.0 / 60.0);
      free.predict(1.0 / 60.0);
    }
    EXPECT_EQ(filter.peg_bounces(), 1) << "offset " << offset_mm;
    const Eigen::Matrix4d p = filter.covariance();
    EXPECT_LT((p - p.transpose()).cwiseAbs().maxCoeff(), 1e-9);
    EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d>(p).eigenvalues().minCoeff(), 0.0);
    // The reflection keeps the trace of the velocity block without the
    // bounce's own error (restitution 0.5 shrinks it, never grows it).
    return p.bottomRightCorner<2, 2>().trace() -
           free.covariance().bottomRightCorner<2, 2>().trace();
  };
  BallKalmanParams params = params_for(placement);
  params.initial_velocity_sigma_mm_s = 1e-3;  // the incoming velocity known
  BallKalmanParams exact = params;
  exact.peg_position_sigma_mm = 0.0;
  exact.restitution_sigma = 0.0;
  EXPECT_LT(added_velocity_variance(5.0, exact), 1.0);  // (mm/s)^2: nothing added
  const double head_on = added_velocity_variance(5.0, params);
  const double grazing = added_velocity_variance(24.0, params);
  std::printf("added velocity sigma: head-on %.0f mm/s, grazing %.0f mm/s\n", std::sqrt(head_on),
              std::sqrt(grazing));
  // Head on at 1 m/s: (1 + e) 1000 mm/s x 0.5 mm / 26 mm ~ 29 mm/s and the
  // restitution's 0.05 x 1000 mm/s.
  EXPECT_GT(std::sqrt(head_on), 25.0);
  EXPECT_LT(std::sqrt(head_on), 80.0);
  EXPECT_GT(grazing, 1.5 * head_on);  // 86 against 61 mm/s at 24 and 5 mm off centre

  BallKalmanParams bad = params;
  bad.bounce_min_cos = 0.0;
  EXPECT_THROW(BallKalmanFilter{bad}, std::invalid_argument);
  bad = params;
  bad.peg_position_sigma_mm = -1.0;
  EXPECT_THROW(BallKalmanFilter{bad}, std::invalid_argument);
}

TEST(BallKalmanFilterTest, FirstContactOnAStep) {
  const Eigen::Vector2d c(0.0, 0.0);
  EXPECT_NEAR(first_contact({0.0, -30.0}, {0.0, -20.0}, c, 26.0), 0.4, 1e-12);
  EXPECT_EQ(first_contact({0.0, -25.0}, {0.0, -20.0}, c, 26.0), 0.0);    // inside already
  EXPECT_EQ(first_contact({30.0, -30.0}, {30.0, -20.0}, c, 26.0), 1.0);  // passes by
}

// The bounce is taken at the contact, not where the 2 ms step left the
// ball inside the peg: 20 mm off centre at 1 m/s the normal is
// (20, -16.61) / 26 and the ball leaves at (737, 388) mm/s.
TEST(BallKalmanFilterTest, PredictReflectsAtTheContactPoint) {
  BallKalmanParams params;
  params.acceleration_mm_s2 = 0.0;
  BallKalmanFilter filter(params);
  filter.set_pegs({Eigen::Vector2d(280.0, 300.0)}, 26.0);
  filter.initialise({300.0, 250.0}, Eigen::Matrix2d::Identity(), Eigen::Vector2d(0.0, 1000.0));
  for (int i = 0; i < 6; ++i) filter.predict(1.0 / 60.0);
  ASSERT_EQ(filter.peg_bounces(), 1);
  const Eigen::Vector2d n = Eigen::Vector2d(20.0, -std::sqrt(26.0 * 26.0 - 400.0)) / 26.0;
  const Eigen::Vector2d v_in(0.0, 1000.0);
  const Eigen::Vector2d expected = v_in - 1.5 * v_in.dot(n) * n;
  EXPECT_NEAR(filter.velocity().x(), expected.x(), 1.0);
  EXPECT_NEAR(filter.velocity().y(), expected.y(), 1.0);
}

}  // namespace
}  // namespace ephor::catching
