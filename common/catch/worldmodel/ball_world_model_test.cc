#include "common/catch/worldmodel/ball_world_model.h"

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "common/catch/worldmodel/test_scene.h"

namespace ephor::catching {
namespace {

constexpr int64_t kFrameUs = 16667;  // 60 Hz
constexpr double kPixelNoise = 0.3;  // px per axis

class BallWorldModelTest : public ::testing::Test {
 protected:
  BallWorldModelTest() { params_.pixel_sigma_px = kPixelNoise; }
  BallWorldModel make() {
    return BallWorldModel(board_, placement_, intrinsics_, board_to_camera_, params_);
  }
  // The ball centre at (x, y) of B as the vision would see it.
  Eigen::Vector2d pixel_of(const Eigen::Vector2d& p_b) {
    const BoardRay ray(board_, placement_, intrinsics_, board_to_camera_);
    const auto px = ray.project(Eigen::Vector3d(p_b.x(), p_b.y(), board_.ball_radius_mm()));
    return *px + Eigen::Vector2d(noise_(rng_), noise_(rng_));
  }
  Eigen::Vector2d pixel_of_w(const Eigen::Vector3d& p_w) {
    const BoardRay ray(board_, placement_, intrinsics_, board_to_camera_);
    const Eigen::Vector3d p_b = board_to_world(board_, placement_).inverse() * p_w;
    return *ray.project(p_b) + Eigen::Vector2d(noise_(rng_), noise_(rng_));
  }
  std::vector<testing::RollingSample> roll(Eigen::Vector2d p0, Eigen::Vector2d v0) {
    return testing::simulate_roll(board_, testing::rolling_acceleration(placement_), p0, v0,
                                  1e-6 * kFrameUs, 0.0, 1);
  }

  BoardSpec board_;
  BoardPlacement placement_;
  CameraIntrinsics intrinsics_;
  Pose board_to_camera_ = testing::camera_looking_at_board(board_);
  BallWorldModelParams params_;
  std::mt19937 rng_{42};
  std::normal_distribution<double> noise_{0.0, kPixelNoise};
};

TEST_F(BallWorldModelTest, FollowsABallFromReleaseToExitAndPredictsTheCatch) {
  BallWorldModel wm = make();
  const int64_t t0 = 1'700'000'000'000'000;  // a wall-clock utime
  int64_t t = t0;
  for (int k = 0; k < 5; ++k, t += kFrameUs) {
    EXPECT_EQ(wm.update(t, std::nullopt).status, BallStatus::kNoBall);
  }
  const Eigen::Vector2d p0(220.0, 40.0), v0(140.0, 30.0);
  const auto track = roll(p0, v0);
  const int64_t release = t;
  // The truth: exit and catch.
  const double a = testing::rolling_acceleration(placement_);
  const double tau =
      (-v0.y() + std::sqrt(v0.y() * v0.y() + 2.0 * a * (board_.height_mm - p0.y()))) / a;
  const double exit_x = p0.x() + v0.x() * tau;
  const BallisticCrossing truth =
      ballistic_crossing(board_, placement_, exit_x, v0.x(), v0.y() + a * tau);
  const int64_t true_catch = release + std::llround((tau + truth.flight_s) * 1e6);

  bool checked_half_second = false;
  for (std::size_t k = 0; k < track.size(); ++k, t += kFrameUs) {
    const BallFrame& f = wm.update(t, pixel_of(track[k].position_mm));
    ASSERT_EQ(f.status, BallStatus::kTracking) << k;
    EXPECT_EQ(f.acquired, k == 0);
    EXPECT_EQ(f.ball_id, 1);
    ASSERT_TRUE(f.has_state);
    ASSERT_TRUE(f.has_prediction);
    EXPECT_LT((f.position_b_mm - track[k].position_mm).norm(), 4.0) << k;
    const double ahead = tau - track[k].t_s;
    if (!checked_half_second && ahead <= 0.5) {
      checked_half_second = true;
      const double err = (f.exit.catch_point_w_mm - truth.point_w_mm).norm();
      std::printf(
          "0.5 s ahead: catch point error %.2f mm (sigma %.2f), catch time error %+.2f ms\n", err,
          f.exit.sigma_catch_mm, 1e-3 * static_cast<double>(f.catch_utime - true_catch));
      EXPECT_LT(err, 10.0);
      EXPECT_LT(std::abs(f.catch_utime - true_catch), 10'000);
    }
  }
  // Past the edge: the falling ball is still seen, its ray meets the board
  // plane beyond the edge; the world model reports the exit and repeats the
  // last prediction.
  const Eigen::Isometry3d b2w = board_to_world(board_, placement_);
  const Eigen::Vector3d edge =
      b2w * Eigen::Vector3d(exit_x, board_.height_mm, board_.ball_radius_mm());
  const BallFrame last_tracking = wm.last();
  for (int k = 0; k < 5; ++k, t += kFrameUs) {
    const double s = 1e-6 * static_cast<double>(t - release) - tau;
    const Eigen::Vector3d v = b2w.linear() * Eigen::Vector3d(v0.x(), v0.y() + a * tau, 0.0);
    const Eigen::Vector3d p = edge + v * s - Eigen::Vector3d(0.0, 0.0, 0.5 * kGravityMmS2 * s * s);
    const BallFrame& f = wm.update(t, pixel_of_w(p));
    EXPECT_EQ(f.status, BallStatus::kExited) << k;
    ASSERT_TRUE(f.has_prediction);
    EXPECT_EQ(f.catch_utime, last_tracking.catch_utime);
    EXPECT_EQ(f.exit.catch_point_w_mm, last_tracking.exit.catch_point_w_mm);
  }
  const double final_err = (wm.last().exit.catch_point_w_mm - truth.point_w_mm).norm();
  std::printf("last prediction: catch point error %.2f mm, catch time error %+.2f ms\n", final_err,
              1e-3 * static_cast<double>(wm.last().catch_utime - true_catch));
  EXPECT_LT(final_err, 5.0);
  EXPECT_LT(std::abs(wm.last().catch_utime - true_catch), 5'000);
  EXPECT_EQ(wm.exits(), 1);
  // After the hold, no ball.
  t += std::llround(params_.exited_hold_s * 1e6);
  EXPECT_EQ(wm.update(t, std::nullopt).status, BallStatus::kNoBall);
  // A new ball near the top is ball 2.
  t += kFrameUs;
  const BallFrame& next = wm.update(t, pixel_of({300.0, 30.0}));
  EXPECT_EQ(next.status, BallStatus::kTracking);
  EXPECT_EQ(next.ball_id, 2);
}

TEST_F(BallWorldModelTest, RejectsASpuriousCentroidAndKeepsTracking) {
  BallWorldModel wm = make();
  const auto track = roll({300.0, 40.0}, {0.0, 100.0});
  int64_t t = 0;
  for (std::size_t k = 0; k < 30; ++k, t += kFrameUs) {
    const bool spurious = k == 20;
    const Eigen::Vector2d px = spurious
                                   ? pixel_of(track[k].position_mm + Eigen::Vector2d(150.0, 200.0))
                                   : pixel_of(track[k].position_mm);
    const BallFrame& f = wm.update(t, px);
    if (spurious) {
      EXPECT_EQ(f.status, BallStatus::kRejected);
      EXPECT_EQ(f.reason, RejectReason::kJump);
      EXPECT_TRUE(f.has_state);  // the track coasts
      EXPECT_TRUE(f.has_prediction);
      EXPECT_LT((f.position_b_mm - track[k].position_mm).norm(), 4.0);
    } else {
      EXPECT_EQ(f.status, BallStatus::kTracking) << k;
      EXPECT_EQ(f.ball_id, 1);
    }
  }
  EXPECT_EQ(wm.gate().rejected(RejectReason::kJump), 1);
}

TEST_F(BallWorldModelTest, OffBoardCentroidWithoutABallIsRejected) {
  BallWorldModel wm = make();
  const BallFrame& f = wm.update(0, pixel_of({-80.0, 300.0}));
  EXPECT_EQ(f.status, BallStatus::kRejected);
  EXPECT_EQ(f.reason, RejectReason::kOffBoard);
  EXPECT_TRUE(f.has_measurement);
  EXPECT_FALSE(f.has_state);
}

TEST_F(BallWorldModelTest, LosesABallThatIsNoLongerSeen) {
  BallWorldModel wm = make();
  const auto track = roll({300.0, 40.0}, {0.0, 0.0});
  int64_t t = 0;
  for (std::size_t k = 0; k < 15; ++k, t += kFrameUs) wm.update(t, pixel_of(track[k].position_mm));
  // Coasting: still TRACKING (with a growing covariance) up to coast_limit_s.
  const double sigma0 = std::sqrt(wm.last().covariance(0, 0));
  const BallFrame& coast = wm.update(t, std::nullopt);
  EXPECT_EQ(coast.status, BallStatus::kTracking);
  EXPECT_GT(std::sqrt(coast.covariance(0, 0)), sigma0);
  t += std::llround((params_.coast_limit_s + 0.01) * 1e6);
  EXPECT_EQ(wm.update(t, std::nullopt).status, BallStatus::kNoBall);
  EXPECT_EQ(wm.lost(), 1);
}

// The arm moving in view near the board's foot makes motion in the
// difference image: with no ball tracked, that must not start a "ball" (and
// so reach Prim); a real ball released at the top still does.
TEST_F(BallWorldModelTest, MotionLowOnTheBoardWithoutABallStartsNoBall) {
  params_.acquire_max_y_mm = board_.height_mm / 3.0;
  BallWorldModel model = make();
  int64_t t = 1'000'000;
  for (int i = 0; i < 20; ++i, t += kFrameUs) {
    const BallFrame& f = model.update(t, pixel_of(Eigen::Vector2d(250.0 + 3.0 * i, 800.0)));
    EXPECT_EQ(f.status, BallStatus::kRejected) << "frame " << i;
    EXPECT_EQ(f.reason, RejectReason::kNotAtStart);
    EXPECT_FALSE(f.has_prediction);
  }
  for (int i = 0; i < 5; ++i, t += kFrameUs)
    model.update(t, pixel_of(Eigen::Vector2d(300.0, 60.0 + i)));
  EXPECT_EQ(model.last().status, BallStatus::kTracking);
}

TEST_F(BallWorldModelTest, OutOfOrderFrameChangesNothing) {
  BallWorldModel wm = make();
  wm.update(100'000, pixel_of({300.0, 100.0}));
  const Eigen::Vector2d before = wm.filter().position();
  const BallFrame& f = wm.update(100'000, pixel_of({300.0, 140.0}));
  EXPECT_EQ(f.status, BallStatus::kRejected);
  EXPECT_EQ(f.reason, RejectReason::kOutOfOrder);
  EXPECT_EQ(wm.filter().position(), before);
  EXPECT_EQ(wm.out_of_order(), 1);
}

// Found by the fuzz target catch_world_model: a capture time years after the
// last one made the filter's step count overflow int (UB) and step the pegs
// for hours; times far apart overflowed int64.
TEST_F(BallWorldModelTest, AGapLongerThanTheCoastLimitLosesTheBall) {
  BallWorldModel wm = make();
  int64_t t = 1'700'000'000'000'000;
  for (const auto& s : roll({300.0, 40.0}, {0.0, 50.0})) {
    wm.update(t, pixel_of(s.position_mm));
    t += kFrameUs;
    if (s.position_mm.y() > 200.0) break;
  }
  ASSERT_EQ(wm.last().status, BallStatus::kTracking);
  const BallFrame& f = wm.update(t + int64_t{1'000'000'000'000'000}, std::nullopt);
  EXPECT_EQ(f.status, BallStatus::kNoBall);
  EXPECT_EQ(wm.lost(), 1);
}

TEST_F(BallWorldModelTest, ACaptureTimeOutOfRangeIsRefused) {
  BallWorldModel wm = make();
  for (const int64_t t :
       {int64_t{-5}, std::numeric_limits<int64_t>::min(), std::numeric_limits<int64_t>::max()}) {
    const BallFrame& f = wm.update(t, pixel_of({300.0, 100.0}));
    EXPECT_EQ(f.status, BallStatus::kRejected) << t;
    EXPECT_EQ(f.reason, RejectReason::kNotFinite) << t;
  }
  EXPECT_EQ(wm.update(100'000, std::nullopt).status, BallStatus::kNoBall);  // nothing kept
}

}  // namespace
}  // namespace ephor::catching
