#include "common/catch/board_survey.h"

#include <random>

#include <gtest/gtest.h>

namespace ephor::catching {
namespace {

TEST(BoardSurvey, ThreeTouchedPointsGiveTheInclineAndTheEdge) {
  BoardSpec board;
  BoardPlacement truth;
  truth.incline_rad = 27.0 * M_PI / 180.0;
  const Pose b2w = board_to_world(board, truth);
  std::array<Eigen::Vector2d, 3> b{Eigen::Vector2d(50, 50), Eigen::Vector2d(550, 50),
                                   Eigen::Vector2d(300, 850)};
  std::array<Eigen::Vector3d, 3> w;
  std::mt19937_64 rng(3);
  std::normal_distribution<double> noise(0.0, 0.5);
  for (int i = 0; i < 3; ++i)
    w[i] = b2w * Eigen::Vector3d(b[i].x(), b[i].y(), 0.0) +
           Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
  std::string why;
  const auto p = placement_from_survey(board, b, w, why);
  ASSERT_TRUE(p) << why;
  EXPECT_NEAR(p->incline_rad * 180.0 / M_PI, 27.0, 0.15);
  EXPECT_LT((p->bottom_centre_w_mm - truth.bottom_centre_w_mm).norm(), 2.0);
}

TEST(BoardSurvey, BadSurveysAreRefusedSayingWhy) {
  BoardSpec board;
  const Pose b2w = board_to_world(board, BoardPlacement{});
  std::array<Eigen::Vector2d, 3> b{Eigen::Vector2d(50, 50), Eigen::Vector2d(300, 50),
                                   Eigen::Vector2d(550, 50)};
  std::array<Eigen::Vector3d, 3> w;
  for (int i = 0; i < 3; ++i) w[i] = b2w * Eigen::Vector3d(b[i].x(), b[i].y(), 0.0);
  std::string why;
  EXPECT_FALSE(placement_from_survey(board, b, w, why));
  EXPECT_NE(why.find("collinear"), std::string::npos) << why;
  b[2] = Eigen::Vector2d(300, 850);
  w[2] = b2w * Eigen::Vector3d(300, 850, 0.0) + Eigen::Vector3d(0, 0, 40);  // touched 40 mm off
  EXPECT_FALSE(placement_from_survey(board, b, w, why));
  EXPECT_NE(why.find("do not fit"), std::string::npos) << why;
}

}  // namespace
}  // namespace ephor::catching
