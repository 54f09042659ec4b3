#include "common/camera/frame_source.h"

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "common/camera/channel_converter.h"

namespace ephor::camera {
namespace {

namespace fs = std::filesystem;

class FrameSourceTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("ephor_frame_source_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  // A 64 x 48 BGR frame whose green level is 10 * i (red and blue 0).
  static cv::Mat frame(int i) { return cv::Mat(48, 64, CV_8UC3, cv::Scalar(0, 10 * i, 0)); }
  // Message of the runtime_error `spec` raises ("" when it opens).
  static std::string open_error(const std::string& spec) {
    try {
      FrameSource source(spec);
    } catch (const std::runtime_error& e) {
      return e.what();
    }
    return "";
  }
  fs::path dir_;
};

TEST_F(FrameSourceTest, ImageSequenceInOrderThenEnd) {
  for (int i = 0; i < 5; ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "%04d.png", i);
    ASSERT_TRUE(cv::imwrite((dir_ / name).string(), frame(i)));
  }
  FrameSource source((dir_ / "%04d.png").string());
  EXPECT_EQ(source.kind(), SourceKind::kImageSequence);
  EXPECT_EQ(source.width(), 64);
  EXPECT_EQ(source.height(), 48);
  ChannelConverter green;
  std::vector<uint8_t> grey;
  cv::Mat m;
  for (int i = 0; i < 5; ++i) {
    ASSERT_TRUE(source.read(m)) << i;
    green.convert(m, grey);
    EXPECT_EQ(grey[100], 10 * i);  // lossless PNG: the exact level
  }
  EXPECT_FALSE(source.read(m));
  source.rewind();
  ASSERT_TRUE(source.read(m));
  green.convert(m, grey);
  EXPECT_EQ(grey[100], 0);
}

TEST_F(FrameSourceTest, VideoFileStatesItsFrameRate) {
  const std::string path = (dir_ / "clip.avi").string();
  {
    cv::VideoWriter writer(path, cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), 25.0,
                           cv::Size(64, 48));
    ASSERT_TRUE(writer.isOpened());
    for (int i = 0; i < 8; ++i) writer.write(frame(10 + i));
  }
  FrameSource source(path);
  EXPECT_EQ(source.kind(), SourceKind::kVideoFile);
  EXPECT_DOUBLE_EQ(source.stated_fps(), 25.0);
  ChannelConverter green;
  std::vector<uint8_t> grey;
  cv::Mat m;
  int frames = 0;
  while (source.read(m)) {
    green.convert(m, grey);
    EXPECT_NEAR(grey[100], 10 * (10 + frames), 4);  // JPEG: close, not exact
    ++frames;
  }
  EXPECT_EQ(frames, 8);
}

TEST_F(FrameSourceTest, BadSourcesAreNamed) {
  EXPECT_NE(open_error((dir_ / "missing.avi").string()).find("no such file"), std::string::npos);
  EXPECT_NE(open_error((dir_ / "frames_%s.png").string()).find("bad pattern"), std::string::npos);
  EXPECT_NE(open_error((dir_ / "%04d_%04d.png").string()).find("bad pattern"), std::string::npos);
  EXPECT_NE(open_error((dir_ / "none_%04d.png").string()).find("no file for frame"),
            std::string::npos);
  EXPECT_NE(open_error("/dev/video97").find("no such device"), std::string::npos);
  const std::string text = (dir_ / "notes.avi").string();
  std::ofstream(text) << "not a video\n";
  const std::string msg = open_error(text);
  EXPECT_NE(msg.find("notes.avi"), std::string::npos) << msg;
  EXPECT_FALSE(msg.empty());
}

// Found by the fuzz target video_file_camera (procs/shared/camera): an AVI
// FFmpeg refuses and OpenCV's own AVI reader opens, then asserts on (a chunk
// of 4 GB): the cv::Exception escaped FrameSource::read, and ephor-camera's
// task logged it at every period instead of stopping with the file's name.
TEST(FrameSourceFaults, AFrameOpenCvFailsOnIsAnErrorNamingTheFile) {
  const std::string path =
      (std::filesystem::path(__FILE__).parent_path().parent_path().parent_path() /
       "procs/shared/camera/fuzz_corpus/video_file_camera/crash-opencv-avi-chunk-assert.avi")
          .string();
  ASSERT_TRUE(std::filesystem::exists(path)) << path;
  std::string error;
  try {
    FrameSource source(path);
    cv::Mat frame;
    for (int i = 0; i < 100 && source.read(frame); ++i) {
    }
  } catch (const std::runtime_error& e) {
    error = e.what();
  }
  EXPECT_NE(error.find(path), std::string::npos) << error;
  EXPECT_NE(error.find("cannot decode"), std::string::npos) << error;
}

TEST(SourceKindTest, FromTheFormOfTheSpec) {
  EXPECT_EQ(classify_source("/dev/video0"), SourceKind::kDevice);
  EXPECT_EQ(classify_source("2"), SourceKind::kDevice);
  EXPECT_EQ(classify_source("frames/%04d.png"), SourceKind::kImageSequence);
  EXPECT_EQ(classify_source("vtest.avi"), SourceKind::kVideoFile);
  EXPECT_EQ(check_sequence_pattern("a/%d.png"), "");
  EXPECT_EQ(check_sequence_pattern("100%%_%03d.jpg"), "");
  EXPECT_NE(check_sequence_pattern("plain.png"), "");
}

}  // namespace
}  // namespace ephor::camera
