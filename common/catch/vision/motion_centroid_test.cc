#include "common/catch/vision/motion_centroid.h"

#include <cmath>
#include <iostream>

#include <gtest/gtest.h>

#include "common/catch/vision/test_scenes.h"

namespace ephor::catching {
namespace {

constexpr double kPi = 3.14159265358979323846;

// A ball rolling straight down the slope of a board seen at 1.5 m, 25 deg
// off its normal; `step_mm` per 1/60 s frame.
struct RollingBall {
  SyntheticScene scene = testing::board_scene(1500.0, 25.0);
  double x_mm = 230.0, y0_mm = 250.0, step_mm = 10.0;
  Eigen::Vector2d where_mm(int k) const { return {x_mm + 0.3 * step_mm * k, y0_mm + step_mm * k}; }
  Eigen::Vector2d true_px(int k) const {
    const Eigen::Vector2d p = where_mm(k);
    return project_pinhole(scene.camera, scene.board_to_camera,
                           Eigen::Vector3d(p.x(), p.y(), scene.board.ball_radius_mm()));
  }
  cv::Mat frame(int k, double contrast, uint64_t seed) const {
    SyntheticScene s = scene;
    s.ball = SyntheticBall{where_mm(k), contrast};
    return render_board(s, 2.0, seed);
  }
};

TEST(CrescentTest, DisplacementFromSeparationInvertsTheCrescentModel) {
  EXPECT_NEAR(displacement_from_crescent_separation(25.0, 8.0), 25.0, 1e-12);
  // Small displacement: two thin crescents pi r / 4 either side.
  EXPECT_NEAR(displacement_from_crescent_separation(kPi * 8.0 / 2.0 + 1e-6, 8.0), 0.0, 0.05);
  const double d = displacement_from_crescent_separation(14.0, 8.0);
  EXPECT_GT(d, 0.0);
  EXPECT_LT(d, 14.0);
}

struct Case {
  double contrast;
  double step_mm;  // per 1/60 s; 1/30 s moves twice this
};

class MovingBallTest : public ::testing::TestWithParam<Case> {};

TEST_P(MovingBallTest, FindsTheBallsCentreAndThePlainCentroidLags) {
  const Case c = GetParam();
  RollingBall ball;
  ball.step_mm = c.step_mm;
  // At the top of the board the ball's two positions overlap in every
  // frame, so its radius cannot be learnt: give it, as the world model would
  // (f R / Z).
  // The crescents alone (what is left when the reference image has no disc
  // there); ReferenceImageCentresAReleasedBall tests the reference.
  MotionCentroidOptions options;
  options.background_centre = false;
  const Eigen::Vector3d centre_c =
      ball.scene.board_to_camera *
      Eigen::Vector3d(ball.x_mm, ball.y0_mm + 7 * c.step_mm, ball.scene.board.ball_radius_mm());
  if (2.0 * c.step_mm < ball.scene.board.ball_diameter_mm)
    options.ball_radius_px =
        ball.scene.camera.fx * ball.scene.board.ball_radius_mm() / centre_c.z();
  MotionCentroid motion(options);
  double sum_sq = 0.0, sum_sq_uncorrected = 0.0;
  double worst = 0.0, worst_uncorrected = 0.0, plain_lag = 0.0, half_disp = 0.0;
  int measured = 0;
  MotionCentroidOptions uncorrected_options;
  uncorrected_options.correct_crescent = false;
  uncorrected_options.background_centre = false;
  MotionCentroid uncorrected(uncorrected_options);
  // Known ball radius for the uncorrected one so only the correction differs.
  for (int k = 0; k < 14; ++k) {
    const cv::Mat f = ball.frame(k, c.contrast, 1000 + static_cast<uint64_t>(k));
    const MotionMeasurement m = motion.process(f);
    const MotionMeasurement u = uncorrected.process(f);
    if (k < 2) {
      EXPECT_FALSE(m.found);
      continue;
    }
    ASSERT_TRUE(m.found) << "frame " << k;
    if (!m.ball_centre) continue;  // the contrast sign is still being learnt
    EXPECT_EQ(m.contrast_sign, c.contrast > 0 ? 1 : -1);
    ++measured;
    const Eigen::Vector2d truth = ball.true_px(k);
    worst = std::max(worst, (m.centroid_px - truth).norm());
    sum_sq += (m.centroid_px - truth).squaredNorm();
    if (u.ball_centre) {
      worst_uncorrected = std::max(worst_uncorrected, (u.centroid_px - truth).norm());
      sum_sq_uncorrected += (u.centroid_px - truth).squaredNorm();
    }
    plain_lag += (m.plain_centroid_px - truth).norm();
    half_disp += 0.5 * (truth - ball.true_px(k - 2)).norm();
  }
  ASSERT_GE(measured, 6) << "the contrast sign was not learnt";
  plain_lag /= measured;
  half_disp /= measured;
  const double rms_error = std::sqrt(sum_sq / measured);
  const double rms_uncorrected = std::sqrt(sum_sq_uncorrected / measured);
  std::cout << "contrast " << c.contrast << ", " << 2 * c.step_mm << " mm per 1/30 s ("
            << 2 * half_disp << " px): ball-centre error RMS " << rms_error << " worst " << worst
            << " px (uncorrected 'now' centroid RMS " << rms_uncorrected << " worst "
            << worst_uncorrected << " px), plain centroid lag " << plain_lag
            << " px, half the displacement " << half_disp << " px, learnt radius "
            << motion.learnt_radius_px() << " px\n";
  EXPECT_NEAR(plain_lag, half_disp, 0.2 * half_disp + 0.3);
  if (2.0 * c.step_mm >= ball.scene.board.ball_diameter_mm) {
    // The bottom of the board: the two positions are apart.
    EXPECT_LT(rms_error, 0.5);
    EXPECT_LT(worst, 1.0);
  } else {
    // The top: overlapping positions, crescents of a few grey levels.
    EXPECT_LT(rms_error, 0.6 * plain_lag);
  }
}

INSTANTIATE_TEST_SUITE_P(Contrasts, MovingBallTest,
                         ::testing::Values(Case{5.0, 37.5}, Case{-5.0, 37.5}, Case{5.0, 30.0},
                                           Case{-5.0, 45.0}, Case{5.0, 10.0}, Case{-5.0, 10.0}));

// A ball released at the top and rolling away from rest (2500 mm/s^2, a
// 25-degree board): absent in frames 0-5, then slow enough that its two
// positions 1/30 s apart overlap for the first 0.15 s. Against the reference
// image the whole disc is seen from the first frame on and its centre is
// within a fraction of a pixel; the crescents alone are pixels off.
struct ReleasedBall {
  SyntheticScene scene = testing::board_scene(1500.0, 25.0);
  static constexpr int kRelease = 6;
  Eigen::Vector2d where_mm(int k) const {
    const double t = (k - kRelease) / 60.0;
    return {300.0, 60.0 + 0.5 * 2500.0 * t * t};
  }
  Eigen::Vector2d true_px(int k) const {
    const Eigen::Vector2d p = where_mm(k);
    return project_pinhole(scene.camera, scene.board_to_camera,
                           Eigen::Vector3d(p.x(), p.y(), scene.board.ball_radius_mm()));
  }
  cv::Mat frame(int k, double contrast, uint64_t seed) const {
    SyntheticScene s = scene;
    if (k >= kRelease) s.ball = SyntheticBall{where_mm(k), contrast};
    return render_board(s, 2.0, seed);
  }
};

struct ReleaseErrors {
  int measured = 0;
  double rms = 0.0, worst = 0.0;
};

ReleaseErrors track_release(MotionCentroidOptions options, double contrast) {
  options.contrast_sign = contrast > 0 ? 1 : -1;  // as learnt from earlier balls
  MotionCentroid motion(options);
  ReleasedBall ball;
  ReleaseErrors e;
  for (int k = 0; k < ReleasedBall::kRelease + 24; ++k) {
    const MotionMeasurement m = motion.process(ball.frame(k, contrast, 500 + k));
    if (k < ReleasedBall::kRelease) {
      EXPECT_FALSE(m.found) << "frame " << k << ": no ball yet";
      continue;
    }
    if (!m.found || !m.ball_centre) continue;
    const double err = (m.centroid_px - ball.true_px(k)).norm();
    ++e.measured;
    e.rms += err * err;
    e.worst = std::max(e.worst, err);
  }
  if (e.measured > 0) e.rms = std::sqrt(e.rms / e.measured);
  return e;
}

TEST(MotionCentroidTest, ReferenceImageCentresAReleasedBall) {
  for (const double contrast : {5.0, -5.0}) {
    MotionCentroidOptions with, without;
    without.background_centre = false;
    const ReleaseErrors a = track_release(with, contrast);
    const ReleaseErrors b = track_release(without, contrast);
    std::cout << "contrast " << contrast << ": against the reference " << a.measured
              << " frames, RMS " << a.rms << " worst " << a.worst << " px; crescents only "
              << b.measured << " frames, RMS " << b.rms << " worst " << b.worst << " px\n";
    EXPECT_GE(a.measured, 23);  // every frame but perhaps the first
    EXPECT_LT(a.rms, 0.5);
    EXPECT_LT(a.worst, 1.2);
    EXPECT_LT(a.rms, 0.5 * b.rms);
  }
}

TEST(MotionCentroidTest, PartlyHiddenDiscIsNotMeasured) {
  // The ball rolls on behind a dark bar (the arm) drawn over the board: the
  // visible part of its disc would pull the centre; none is reported.
  ReleasedBall ball;
  MotionCentroidOptions options;
  options.contrast_sign = 1;
  MotionCentroid motion(options);
  const int hidden_from = ReleasedBall::kRelease + 20;
  int hidden = 0, wrong = 0;
  for (int k = 0; k < hidden_from + 4; ++k) {
    cv::Mat f = ball.frame(k, 5.0, 900 + k);
    // The bar covers everything beyond the ball's position in frame hidden_from.
    const double edge_v = ball.true_px(hidden_from).y();
    f.rowRange(static_cast<int>(std::ceil(edge_v)), f.rows).setTo(30);
    const MotionMeasurement m = motion.process(f);
    if (k < hidden_from) continue;
    if (m.hidden) ++hidden;
    if (m.found && (m.centroid_px - ball.true_px(k)).norm() > 2.0) ++wrong;
  }
  EXPECT_GE(hidden, 1);
  EXPECT_EQ(wrong, 0) << "a partly hidden disc gave a centre more than 2 px off";
}

TEST(MotionCentroidTest, BallAppearingUnderAWrongSignLeavesNoGhost) {
  // Something of the opposite contrast moves first (as the arm did before
  // the first ball) and teaches the sign -1; then a ball of contrast +5 is
  // released. The reference must not take the unconfirmed ball in: its
  // ghost at the release point has the learnt sign, and the vision centred
  // every later frame on it (seed 3 live, seed 4 in the harness).
  ReleasedBall ball;
  MotionCentroid motion;
  RollingBall other;
  other.step_mm = 20.0;
  for (int k = 0; k < 14; ++k) motion.process(other.frame(k, -5.0, 300 + static_cast<uint64_t>(k)));
  ASSERT_EQ(motion.learnt_sign(), -1);
  const SyntheticScene empty = ball.scene;
  for (int i = 0; i < 10; ++i)
    motion.process(render_board(empty, 2.0, 700 + static_cast<uint64_t>(i)));
  int ghost = 0, found_later = 0;
  for (int j = 0; j < ReleasedBall::kRelease + 24; ++j) {
    const MotionMeasurement m = motion.process(ball.frame(j, 5.0, 800 + static_cast<uint64_t>(j)));
    if (j < ReleasedBall::kRelease + 8 || !m.found) continue;
    ++found_later;
    // The ball has moved well away from its release point by now.
    if ((m.centroid_px - ball.true_px(ReleasedBall::kRelease)).norm() < 2.0) ++ghost;
  }
  std::cout << "found in " << found_later << " of the last 16 frames, on the ghost in " << ghost
            << "\n";
  EXPECT_EQ(ghost, 0) << "centred on the ball's ghost at the release point";
}

TEST(MotionCentroidTest, NoBallMeansNotFound) {
  RollingBall ball;
  MotionCentroid motion;
  for (int k = 0; k < 12; ++k) {
    const MotionMeasurement m =
        motion.process(render_board(ball.scene, 2.0, 500 + static_cast<uint64_t>(k)));
    EXPECT_FALSE(m.found) << "frame " << k << " area " << m.area_px;
  }
}

TEST(MotionCentroidTest, WindowRestrictsDetection) {
  RollingBall ball;
  ball.step_mm = 37.5;
  MotionCentroidOptions o;
  o.contrast_sign = 1;
  MotionCentroid inside(o), outside(o), full(o);
  for (int k = 0; k < 6; ++k) {
    const cv::Mat f = ball.frame(k, 5.0, 40 + static_cast<uint64_t>(k));
    const Eigen::Vector2d t = ball.true_px(k);
    const cv::Rect around(static_cast<int>(t.x()) - 40, static_cast<int>(t.y()) - 40, 80, 80);
    const cv::Rect elsewhere(20, 20, 80, 80);
    const MotionMeasurement a = inside.process(f, around);
    const MotionMeasurement b = outside.process(f, elsewhere);
    const MotionMeasurement c = full.process(f);
    if (k < 2) continue;
    ASSERT_TRUE(a.found);
    EXPECT_FALSE(b.found);
    ASSERT_TRUE(c.found);
    EXPECT_LT((a.centroid_px - t).norm(), 1.0);
    EXPECT_LT((a.centroid_px - c.centroid_px).norm(), 0.05) << "windowed and full frame differ";
  }
}

TEST(Mog2CentroidTest, FindsTheMovingBall) {
  RollingBall ball;
  ball.step_mm = 37.5;
  Mog2Centroid mog;
  // Learn the empty board first.
  for (int k = 0; k < 30; ++k)
    mog.process(render_board(ball.scene, 2.0, 900 + static_cast<uint64_t>(k)));
  double worst = 0.0;
  int found = 0;
  for (int k = 0; k < 6; ++k) {
    const MotionMeasurement m = mog.process(ball.frame(k, 5.0, 60 + static_cast<uint64_t>(k)));
    if (!m.found) continue;
    ++found;
    worst = std::max(worst, (m.centroid_px - ball.true_px(k)).norm());
  }
  std::cout << "MOG2: found in " << found << " of 6 frames, worst error " << worst << " px\n";
  EXPECT_GE(found, 5);
  EXPECT_LT(worst, 1.5);
}

}  // namespace
}  // namespace ephor::catching
