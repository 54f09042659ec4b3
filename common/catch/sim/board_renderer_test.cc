#include "common/catch/sim/board_renderer.h"

#include <cmath>

#include <gtest/gtest.h>
#include <Eigen/LU>

namespace ephor::catching {
namespace {

// The image of a circle of B's face: the centre of the ellipse that the
// homography maps the circle's conic to.
Eigen::Vector2d projected_ellipse_centre(const CatchScenario& s, const BoardCircle& c) {
  Eigen::Matrix3d k = Eigen::Matrix3d::Identity();
  k(0, 0) = s.intrinsics.fx, k(1, 1) = s.intrinsics.fy;
  k(0, 2) = s.intrinsics.cx, k(1, 2) = s.intrinsics.cy;
  Eigen::Matrix3d rt;
  rt.col(0) = s.board_to_camera.linear().col(0);
  rt.col(1) = s.board_to_camera.linear().col(1);
  rt.col(2) = s.board_to_camera.translation();
  const Eigen::Matrix3d h = k * rt;  // (x, y, 1) of B -> image
  const double r = 0.5 * c.diameter_mm;
  Eigen::Matrix3d conic;
  conic << 1.0, 0.0, -c.x_mm, 0.0, 1.0, -c.y_mm, -c.x_mm, -c.y_mm,
      c.x_mm * c.x_mm + c.y_mm * c.y_mm - r * r;
  const Eigen::Matrix3d hinv = h.inverse();
  const Eigen::Matrix3d q = hinv.transpose() * conic * hinv;
  return -q.topLeftCorner<2, 2>().inverse() * q.topRightCorner<2, 1>();
}

// Where pixel (u, v)'s ray meets the board plane, B.
Eigen::Vector2d board_point(const CatchScenario& s, int u, int v) {
  const Pose c2b = s.board_to_camera.inverse();
  const Eigen::Vector3d o = c2b.translation();
  const Eigen::Vector3d d =
      c2b.linear() * Eigen::Vector3d((u - s.intrinsics.cx) / s.intrinsics.fx,
                                     (v - s.intrinsics.cy) / s.intrinsics.fy, 1.0);
  return (o + (-o.z() / d.z()) * d).head<2>();
}

// Darkness-weighted centroid of a circle: each pixel's coverage by the
// circle, from the lit board's level there (both scale with the light), over
// the pixels that see the board within 10 mm of the circle.
Eigen::Vector2d circle_centroid(const BoardRenderer& renderer, const CatchScenario& s,
                                const cv::Mat& image, const Eigen::Vector2d& around,
                                const BoardCircle& circle) {
  const double ratio = s.appearance.circle_level / s.appearance.board_level;
  double sw = 0.0, su = 0.0, sv = 0.0;
  const int half = 25;
  for (int v = static_cast<int>(around.y()) - half; v <= static_cast<int>(around.y()) + half; ++v) {
    for (int u = static_cast<int>(around.x()) - half; u <= static_cast<int>(around.x()) + half;
         ++u) {
      if (u < 0 || v < 0 || u >= image.cols || v >= image.rows) continue;
      const Eigen::Vector2d p = board_point(s, u, v);
      if (std::hypot(p.x() - circle.x_mm, p.y() - circle.y_mm) > 0.5 * circle.diameter_mm + 10.0)
        continue;
      const double level = static_cast<double>(renderer.board_level().at<float>(v, u));
      const double px = image.type() == CV_8UC1 ? image.at<uint8_t>(v, u)
                                                : static_cast<double>(image.at<float>(v, u));
      const double w = std::clamp((level - px) / (level * (1.0 - ratio)), 0.0, 1.0);
      sw += w, su += w * u, sv += w * v;
    }
  }
  return Eigen::Vector2d(su / sw, sv / sw);
}

TEST(BoardRendererTest, CircleCentroidsMatchTheProjectedEllipses) {
  for (const uint64_t seed : {1u, 2u, 3u}) {
    CatchScenario s = CatchScenario::draw(seed);
    s.pegs.clear();  // keep the windows around the circles clean
    s.appearance.noise_sigma = 2.0;
    BoardRenderer renderer(s);
    cv::Mat frame;
    renderer.render(std::nullopt, {}, frame);
    for (const BoardCircle& c : s.board.circles) {
      const Eigen::Vector2d truth = projected_ellipse_centre(s, c);
      const Eigen::Vector2d clean = circle_centroid(renderer, s, renderer.background(), truth, c);
      const Eigen::Vector2d noisy = circle_centroid(renderer, s, frame, truth, c);
      EXPECT_LT((clean - truth).norm(), 0.05) << "seed " << seed << " noise-free";
      EXPECT_LT((noisy - truth).norm(), 0.5) << "seed " << seed << " with noise";
      // The projected centre of the circle is not the ellipse's centre.
      const Eigen::Vector2d centre = *s.project(Eigen::Vector3d(c.x_mm, c.y_mm, 0.0));
      EXPECT_GT((centre - truth).norm(), 0.001);
    }
  }
}

TEST(BoardRendererTest, BallDiffersFromTheBoardByAtMostEightGreyLevels) {
  for (const uint64_t seed : {5u, 6u}) {
    CatchScenario s = CatchScenario::draw(seed);
    s.pegs.clear();
    s.appearance.noise_sigma = 0.0;
    BoardRenderer renderer(s);
    const Eigen::Vector3d ball(300.0, 450.0, s.board.ball_radius_mm());
    cv::Mat frame, empty;
    const auto uv = renderer.render(ball, {}, frame);
    renderer.render(std::nullopt, {}, empty);
    ASSERT_TRUE(uv.has_value());
    EXPECT_TRUE(uv->isApprox(*s.project(ball)));
    int changed = 0;
    double max_diff = 0.0, ball_sum = 0.0;
    for (int v = static_cast<int>(uv->y()) - 30; v <= static_cast<int>(uv->y()) + 30; ++v) {
      for (int u = static_cast<int>(uv->x()) - 30; u <= static_cast<int>(uv->x()) + 30; ++u) {
        const double d = frame.at<uint8_t>(v, u) - empty.at<uint8_t>(v, u);
        max_diff = std::max(max_diff, std::abs(d));
        if (std::abs(d) >= 2.0) ++changed, ball_sum += frame.at<uint8_t>(v, u);
      }
    }
    EXPECT_LE(max_diff, 8.0) << "seed " << seed;
    EXPECT_GT(changed, 30) << "seed " << seed << ": the ball must show in a difference image";
    // No threshold separates the ball from the board face: the ball's mean
    // lies within the range of the board's pixels.
    double board_min = 255.0, board_max = 0.0;
    for (int v = 0; v < empty.rows; ++v)
      for (int u = 0; u < empty.cols; ++u) {
        const double lvl = static_cast<double>(renderer.board_level().at<float>(v, u));
        const double px = empty.at<uint8_t>(v, u);
        if (std::abs(px - lvl) < 1.0)
          board_min = std::min(board_min, px), board_max = std::max(board_max, px);
      }
    EXPECT_GT(ball_sum / changed, board_min + 4.0) << "seed " << seed;
    EXPECT_LT(ball_sum / changed, board_max - 4.0) << "seed " << seed;
  }
}

TEST(BoardRendererTest, ArmIsDrawnInFrontOfTheBoardAndHiddenBehindIt) {
  CatchScenario s = CatchScenario::draw(9);
  s.appearance.noise_sigma = 0.0;
  BoardRenderer renderer(s);
  const Pose b2w = s.board_to_world();
  cv::Mat empty, front, behind;
  renderer.render(std::nullopt, {}, empty);
  // A link across the board's centre 150 mm in front of the face, and the
  // same link 150 mm behind it.
  auto link_at = [&](double z_b) {
    ArmView arm;
    arm.links_w.push_back(
        {b2w * Eigen::Vector3d(200.0, 450.0, z_b), b2w * Eigen::Vector3d(400.0, 450.0, z_b), 30.0});
    return arm;
  };
  renderer.render(std::nullopt, link_at(150.0), front);
  renderer.render(std::nullopt, link_at(-150.0), behind);
  const Eigen::Vector2d c = *s.project(Eigen::Vector3d(300.0, 450.0, 150.0));
  const int u = static_cast<int>(std::lround(c.x())), v = static_cast<int>(std::lround(c.y()));
  EXPECT_LT(front.at<uint8_t>(v, u), 40);
  EXPECT_GT(empty.at<uint8_t>(v, u), 70);
  EXPECT_EQ(cv::norm(behind, empty, cv::NORM_INF), 0.0) << "a link behind the board is hidden";
  // The cup below the bottom edge, off the board: drawn.
  ArmView cup;
  cup.cup_opening_w_mm = s.placement.bottom_centre_w_mm + Eigen::Vector3d(-150.0, 0.0, -80.0);
  cv::Mat with_cup;
  renderer.render(std::nullopt, cup, with_cup);
  EXPECT_GT(cv::countNonZero(with_cup != empty), 200);
}

TEST(BoardRendererTest, NoiseHasTheScenarioSigmaAndChangesEveryFrame) {
  const CatchScenario s = CatchScenario::draw(12);
  BoardRenderer renderer(s);
  cv::Mat a, b, bg8;
  renderer.render(std::nullopt, {}, a);
  renderer.render(std::nullopt, {}, b);
  cv::Mat diff;
  cv::Mat a32, b32;
  a.convertTo(a32, CV_32F);
  b.convertTo(b32, CV_32F);
  diff = a32 - renderer.background();
  cv::Scalar mean, stddev;
  cv::meanStdDev(diff, mean, stddev);
  EXPECT_NEAR(stddev[0], s.appearance.noise_sigma, 0.2);
  EXPECT_NEAR(mean[0], 0.0, 0.1);
  EXPECT_GT(cv::norm(a32, b32, cv::NORM_L1), 1e5);
}

}  // namespace
}  // namespace ephor::catching
