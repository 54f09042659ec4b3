#include "procs/catch/track/video_input.h"

#include <filesystem>
#include <string>

#include <gtest/gtest.h>

namespace ephor::catching {
namespace {

std::string corpus_file(const std::string& name) {
  return (std::filesystem::path(__FILE__).parent_path() / "fuzz_corpus/video_file_catch_track" /
          name)
      .string();
}

CameraIntrinsics camera_32x24() {
  CameraIntrinsics c;
  c.width = 32;
  c.height = 24;
  c.fx = c.fy = 30.0;
  c.cx = 15.5;
  c.cy = 11.5;
  return c;
}

TEST(VideoInput, FramesOfTheCameraSizeComeOutGrey) {
  const std::string path = corpus_file("mjpg_colour_32x24.avi");
  cv::VideoCapture capture = open_video(path);
  int frames = 0;
  for (cv::Mat f; !(f = next_frame(capture, frames, path, camera_32x24(), "cam.pbtxt")).empty();) {
    EXPECT_EQ(f.type(), CV_8UC1);
    EXPECT_EQ(f.cols, 32);
    EXPECT_EQ(f.rows, 24);
    ++frames;
  }
  EXPECT_EQ(frames, 4);
}

TEST(VideoInput, FramesOfAnotherSizeAreRefusedNamingTheFile) {
  const std::string path = corpus_file("mjpg_colour_40x30.avi");
  cv::VideoCapture capture = open_video(path);
  try {
    next_frame(capture, 0, path, camera_32x24(), "cam.pbtxt");
    FAIL() << "a 40 x 30 frame taken for a 32 x 24 camera";
  } catch (const VideoInputError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}

// Found by the fuzz target video_file_catch_track: an AVI FFmpeg refuses and
// OpenCV's own AVI reader opens, then asserts on (a chunk of 4 GB). The
// cv::Exception escaped next_frame(), and ephor-catch-track reported an
// internal error (status 1) instead of bad input naming the file (status 2).
TEST(VideoInput, AFrameOpenCvFailsOnIsBadInputNamingTheFrame) {
  const std::string path = corpus_file("crash-opencv-avi-chunk-assert.avi");
  std::string error;
  try {
    cv::VideoCapture capture = open_video(path);
    for (int i = 0; i < 100; ++i)
      if (next_frame(capture, i, path, camera_32x24(), "cam.pbtxt").empty()) break;
  } catch (const VideoInputError& e) {
    error = e.what();
  }
  EXPECT_NE(error.find(path), std::string::npos) << error;
  EXPECT_NE(error.find("cannot be decoded"), std::string::npos) << error;
}

}  // namespace
}  // namespace ephor::catching
