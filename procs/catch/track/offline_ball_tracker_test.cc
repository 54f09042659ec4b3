#include "procs/catch/track/offline_ball_tracker.h"

#include <stdexcept>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/catch/vision/test_scenes.h"

namespace ephor::catching {
namespace {

using ::testing::HasSubstr;

OfflineTrackerOptions at_fps(double fps) {
  OfflineTrackerOptions o;
  o.fps = fps;
  return o;
}

TEST(OfflineBallTrackerTest, DifferencesFramesAThirtiethOfASecondApart) {
  const BoardSpec board;
  const CameraIntrinsics camera;
  EXPECT_EQ(OfflineBallTracker(board, camera, at_fps(60.0)).frame_gap(), 2);
  EXPECT_EQ(OfflineBallTracker(board, camera, at_fps(30.0)).frame_gap(), 1);
  EXPECT_EQ(OfflineBallTracker(board, camera, at_fps(25.0)).frame_gap(), 1);
  EXPECT_EQ(OfflineBallTracker(board, camera, at_fps(120.0)).frame_gap(), 4);
  EXPECT_THROW(OfflineBallTracker(board, camera, at_fps(0.0)), std::invalid_argument);
  OfflineTrackerOptions flat = at_fps(60.0);
  flat.incline_deg = 0.0;
  EXPECT_THROW(OfflineBallTracker(board, camera, flat), std::invalid_argument);
}

TEST(OfflineBallTrackerTest, TracksOnlyAfterThePoseIsFoundAndOnlyFramesOfTheCamerasSize) {
  SyntheticScene s = testing::board_scene(1600.0, 20.0);
  OfflineBallTracker tracker(s.board, s.camera, at_fps(60.0));
  EXPECT_THROW(tracker.track(render_board(s, 2.0, 1)), std::logic_error);

  // A covered circle: no pose, the finder's reason, and the tracker still waits.
  SyntheticScene covered = s;
  covered.covered_circles = {1};
  const TrackerInitialisation bad = tracker.initialise(testing::noisy_frames(covered, 3, 2.0, 5));
  EXPECT_FALSE(bad.ok);
  EXPECT_THAT(bad.problem, HasSubstr("top-right"));
  EXPECT_THAT(bad.problem, HasSubstr("in the whole 640 x 480 image and found 3"));
  EXPECT_FALSE(tracker.initialised());

  // Uncovered: the pose, then frames are taken from frame 0.
  const TrackerInitialisation good = tracker.initialise(testing::noisy_frames(s, 3, 2.0, 9));
  ASSERT_TRUE(good.ok) << good.problem;
  EXPECT_TRUE(tracker.initialised());
  EXPECT_LT((tracker.pose().board_to_camera.translation() - s.board_to_camera.translation()).norm(),
            2.0);
  const TrackedFrame f = tracker.track(render_board(s, 2.0, 11));
  EXPECT_EQ(f.frame, 0);
  EXPECT_FALSE(f.ball_b_mm);  // nothing moves yet
  EXPECT_THROW(tracker.track(cv::Mat(240, 320, CV_8UC1, cv::Scalar(0))), std::invalid_argument);
}

TEST(OfflineBallTrackerTest, ToGreyTakesGreyAndColourAndRefusesSixteenBits) {
  const cv::Mat grey(4, 5, CV_8UC1, cv::Scalar(90));
  EXPECT_EQ(to_grey(grey).type(), CV_8UC1);
  const cv::Mat colour(4, 5, CV_8UC3, cv::Scalar(90, 90, 90));
  const cv::Mat converted = to_grey(colour);
  EXPECT_EQ(converted.type(), CV_8UC1);
  EXPECT_EQ(converted.at<uint8_t>(2, 2), 90);
  EXPECT_EQ(to_grey(cv::Mat(4, 5, CV_8UC4, cv::Scalar(1, 2, 3, 4))).type(), CV_8UC1);
  try {
    to_grey(cv::Mat(4, 5, CV_16UC1, cv::Scalar(0)));
    FAIL() << "16-bit accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), HasSubstr("not 8 bits"));
  }
  EXPECT_THROW(to_grey(cv::Mat()), std::invalid_argument);
}

}  // namespace
}  // namespace ephor::catching
