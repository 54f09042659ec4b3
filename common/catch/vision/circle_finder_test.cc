#include "common/catch/vision/circle_finder.h"

#include <iostream>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/catch/board_file.h"
#include "common/catch/vision/test_scenes.h"

namespace ephor::catching {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

// Windows of `half` px around each circle's projected centre.
std::array<cv::Rect, 4> windows_around(const SyntheticScene& s, int half) {
  const BoardPoseEstimator est(s.board, s.camera);
  std::array<cv::Rect, 4> w;
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector2d c = est.project_circle(s.board_to_camera, i).centre_px;
    w[static_cast<size_t>(i)] = cv::Rect(static_cast<int>(c.x()) - half,
                                         static_cast<int>(c.y()) - half, 2 * half, 2 * half);
  }
  return w;
}

double worst_error(const SyntheticScene& s, const CircleFinderResult& r) {
  const BoardPoseEstimator est(s.board, s.camera);
  double worst = 0.0;
  for (int i = 0; i < 4; ++i)
    worst = std::max(worst, (r.circles[static_cast<size_t>(i)].centroid_px -
                             est.project_circle(s.board_to_camera, i).centroid_px)
                                .norm());
  return worst;
}

TEST(CircleFinderTest, CentroidsWithinATenthOfAPixelOfTheProjectedEllipse) {
  for (const auto& [tilt, pan, roll] :
       std::vector<std::array<double, 3>>{{0.0, 0.0, 0.0}, {35.0, 20.0, 8.0}, {60.0, 0.0, -5.0}}) {
    const SyntheticScene s = testing::board_scene(1500.0, tilt, pan, roll);
    const CircleFinder finder(s.board, s.camera);
    const CircleFinderResult r = finder.find(testing::noisy_frames(s, 10, 2.0, 11));
    ASSERT_TRUE(r.found) << r.problem;
    EXPECT_EQ(r.frames_used, 10);
    const double worst = worst_error(s, r);
    std::cout << "tilt " << tilt << " pan " << pan << " roll " << roll
              << ": worst centroid error (10 frames, noise 2) " << worst << " px, labelling score "
              << r.labelling_score << " vs " << r.runner_up_score << "\n";
    EXPECT_LT(worst, 0.1);
  }
}

TEST(CircleFinderTest, LabelsTheCirclesUnderAnyRoll) {
  for (double roll : {90.0, 180.0, 250.0}) {
    const SyntheticScene s = testing::board_scene(1700.0, 20.0, 0.0, roll);
    const CircleFinderResult r = CircleFinder(s.board, s.camera).find(render_board(s, 2.0, 3));
    ASSERT_TRUE(r.found) << "roll " << roll << ": " << r.problem;
    EXPECT_LT(worst_error(s, r), 0.3) << "roll " << roll;
  }
}

TEST(CircleFinderTest, EqualCirclesCannotBeToldApart) {
  SyntheticScene s = testing::board_scene(1500.0, 20.0);
  s.board.circles[0].diameter_mm = 50.0;
  const CircleFinderResult r = CircleFinder(s.board, s.camera).find(render_board(s, 2.0, 5));
  EXPECT_FALSE(r.found);
  EXPECT_THAT(r.problem, HasSubstr("cannot tell the four circles apart"));
  // The operator's windows settle it.
  CircleFinderOptions o;
  o.windows = windows_around(s, 30);
  const CircleFinderResult w = CircleFinder(s.board, s.camera, o).find(render_board(s, 2.0, 5));
  ASSERT_TRUE(w.found) << w.problem;
  EXPECT_LT(worst_error(s, w), 0.3);
}

TEST(CircleFinderTest, CoveredCircleIsNamed) {
  SyntheticScene s = testing::board_scene(1500.0, 25.0);
  s.covered_circles = {2};
  const cv::Mat frame = render_board(s, 2.0, 9);
  const CircleFinderResult r = CircleFinder(s.board, s.camera).find(frame);
  EXPECT_FALSE(r.found);
  // Without windows: the whole image was searched, and bottom-left is named
  // (from this view, with the one circle it cannot be told from).
  EXPECT_THAT(r.problem, AllOf(HasSubstr("bottom-left"), HasSubstr(" at ("),
                               HasSubstr("looked for dark round blobs in the whole 640 x 480 image "
                                         "and found 3")));
  CircleFinderOptions o;
  o.windows = windows_around(s, 30);
  const CircleFinderResult w = CircleFinder(s.board, s.camera, o).find(frame);
  EXPECT_FALSE(w.found);
  const cv::Rect& bl = (*o.windows)[2];
  EXPECT_EQ(w.problem, "circle bottom-left not found: looked in window (" + std::to_string(bl.x) +
                           "," + std::to_string(bl.y) + ")-(" + std::to_string(bl.x + 59) + "," +
                           std::to_string(bl.y + 59) + ")");
}

// Without windows the missing circle is named from where the other three
// are (P3P, their sizes, the board bright around them), or the candidates
// it cannot be told from are; it is never named wrongly.
TEST(CircleFinderTest, TheMissingCircleIsNamedOrItsCandidatesNeverWrongly) {
  struct View {
    double distance_mm, tilt_deg, pan_deg, roll_deg;
  };
  int named = 0, candidates = 0;
  for (const View& v : {View{1500.0, 25.0, 0.0, 0.0}, View{1600.0, 20.0, 15.0, 5.0},
                        View{1700.0, 30.0, -20.0, -10.0}, View{1400.0, 10.0, 40.0, 170.0}}) {
    for (int covered = 0; covered < 4; ++covered) {
      SyntheticScene s = testing::board_scene(v.distance_mm, v.tilt_deg, v.pan_deg, v.roll_deg);
      s.covered_circles = {covered};
      const CircleFinderResult r = CircleFinder(s.board, s.camera).find(render_board(s, 2.0, 3));
      ASSERT_FALSE(r.found);
      if (r.problem.rfind("circle ", 0) == 0) {
        EXPECT_THAT(r.problem,
                    HasSubstr(std::string("circle ") + circle_name(covered) + " not found"));
        ++named;
      } else {
        EXPECT_THAT(r.problem, AllOf(HasSubstr("a circle not found"),
                                     HasSubstr(std::string("the ") + circle_name(covered))));
        ++candidates;
      }
    }
  }
  // 10 of 16 named on 2026-11-25 (covering the large top-left one: always).
  EXPECT_GE(named, 8);
  EXPECT_EQ(named + candidates, 16);
}

TEST(CircleFinderTest, WindowsRestrictTheSearch) {
  const SyntheticScene s = testing::board_scene(1500.0, 25.0);
  CircleFinderOptions o;
  o.windows = windows_around(s, 30);
  std::swap((*o.windows)[0], (*o.windows)[3]);  // the operator's windows decide the labels
  const CircleFinderResult r = CircleFinder(s.board, s.camera, o).find(render_board(s, 2.0, 4));
  ASSERT_TRUE(r.found) << r.problem;
  const BoardPoseEstimator est(s.board, s.camera);
  EXPECT_LT(
      (r.circles[0].centroid_px - est.project_circle(s.board_to_camera, 3).centroid_px).norm(),
      0.3);
  // A window on plain board finds nothing there.
  (*o.windows)[1] = cv::Rect(300, 200, 20, 20);
  const CircleFinderResult none = CircleFinder(s.board, s.camera, o).find(render_board(s, 2.0, 4));
  EXPECT_FALSE(none.found);
  EXPECT_THAT(none.problem, HasSubstr("circle top-right not found"));
}

}  // namespace
}  // namespace ephor::catching
