// ephor-camera as a real process (in a private network namespace): it plays
// an image sequence onto CAMERA and ephor-vision finds the marks in it, as it
// does in ephor-sim's frames; a bad source is named and the process exits 1.

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <mutex>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "common/lcm/bus.h"
#include "common/lcm/channels.h"
#include "common/runtime/channels.h"
#include "ephor/camera_frame_t.hpp"
#include "ephor/shepherd_blobs_t.hpp"
#include "ephor/task_register_t.hpp"
#include "tests/integration/harness.h"

namespace ephor::testing {
namespace {

namespace fs = std::filesystem;
using std::chrono::seconds;

constexpr int kFrames = 10;

// Frame i: a dark green field with two bright green discs (radius 9 px) at
// (80 + 2i, 60) and (220, 150 + i), and a red channel bright everywhere (so
// only the green channel shows the marks).
cv::Mat frame(int i) {
  cv::Mat bgr(240, 320, CV_8UC3, cv::Scalar(20, 30, 250));
  cv::circle(bgr, cv::Point(80 + 2 * i, 60), 9, cv::Scalar(20, 220, 250), cv::FILLED);
  cv::circle(bgr, cv::Point(220, 150 + i), 9, cv::Scalar(20, 220, 250), cv::FILLED);
  return bgr;
}

class Listener {
 public:
  Listener() : bus_("", "test") {
    bus_.subscribe<camera_frame_t>(channels::kCamera, [this](const camera_frame_t& m) {
      std::lock_guard<std::mutex> lock(mutex_);
      frames_.push_back(m);
    });
    bus_.subscribe<shepherd_blobs_t>(channels::kBlobs, [this](const shepherd_blobs_t& m) {
      std::lock_guard<std::mutex> lock(mutex_);
      blobs_.push_back(m);
    });
    bus_.subscribe<task_register_t>(channels::kTaskRegister, [this](const task_register_t& m) {
      std::lock_guard<std::mutex> lock(mutex_);
      if (m.process == "vision") vision_ready_ = true;
    });
    bus_.start();
  }
  ~Listener() { bus_.stop(); }
  std::vector<camera_frame_t> frames() {
    std::lock_guard<std::mutex> lock(mutex_);
    return frames_;
  }
  std::vector<shepherd_blobs_t> blobs() {
    std::lock_guard<std::mutex> lock(mutex_);
    return blobs_;
  }
  bool vision_ready() {
    std::lock_guard<std::mutex> lock(mutex_);
    return vision_ready_;
  }

 private:
  Bus bus_;
  std::mutex mutex_;
  std::vector<camera_frame_t> frames_;
  std::vector<shepherd_blobs_t> blobs_;
  bool vision_ready_ = false;
};

TEST(CameraProcess, ImageSequenceThroughVisionLikeTheSimulatorsCamera) {
  const fs::path dir = fs::temp_directory_path() / ("ephor_camera_" + std::to_string(getpid()));
  fs::create_directories(dir);
  for (int i = 0; i < kFrames; ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "%04d.png", i);
    ASSERT_TRUE(cv::imwrite((dir / name).string(), frame(i)));
  }
  Listener listener;
  Processes procs;
  procs.start("vision", bin("ephor-vision"), {"--no-mlock", "--name", "vision"});
  ASSERT_TRUE(wait_until([&] { return listener.vision_ready(); }, seconds(10)));
  procs.start("camera", bin("ephor-camera"),
              {(dir / "%04d.png").string(), "--fps", "20", "--no-mlock", "--name", "camera"});
  // The camera exits (status 0) after the last frame.
  ASSERT_TRUE(wait_until([&] { return !procs.exits().empty(); }, seconds(15)));
  ASSERT_TRUE(wait_until([&] { return listener.blobs().size() >= kFrames; }, seconds(5)));
  const auto exits = procs.exits();
  ASSERT_EQ(exits.size(), 1u);
  EXPECT_EQ(exits[0].name, "camera");
  EXPECT_FALSE(exits[0].signaled);
  EXPECT_EQ(exits[0].code, 0) << exits[0].describe();

  const auto frames = listener.frames();
  ASSERT_EQ(frames.size(), static_cast<size_t>(kFrames));
  for (int i = 0; i < kFrames; ++i) {
    EXPECT_EQ(frames[i].frame_index, i);
    EXPECT_EQ(frames[i].width, 320);
    EXPECT_EQ(frames[i].height, 240);
    ASSERT_EQ(frames[i].size, 320 * 240);
    EXPECT_EQ(frames[i].data[5 * 320 + 5], 30);  // green of the field, not red
  }
  // 20 frames/s: 50 ms apart, give or take scheduling.
  const double span_ms = static_cast<double>(frames.back().utime - frames.front().utime) / 1e3;
  EXPECT_NEAR(span_ms, 450.0, 60.0);

  for (const auto& b : listener.blobs()) {
    ASSERT_EQ(b.num_blobs, 2) << "frame " << b.frame_index;
    const auto i = static_cast<double>(b.frame_index);
    const shepherd_blob_t& first = b.blobs[0].v < b.blobs[1].v ? b.blobs[0] : b.blobs[1];
    const shepherd_blob_t& second = b.blobs[0].v < b.blobs[1].v ? b.blobs[1] : b.blobs[0];
    EXPECT_NEAR(first.u, 80.0 + 2.0 * i, 0.2);
    EXPECT_NEAR(first.v, 60.0, 0.2);
    EXPECT_NEAR(second.u, 220.0, 0.2);
    EXPECT_NEAR(second.v, 150.0 + i, 0.2);
  }
  fs::remove_all(dir);
}

// A source that cannot be opened is bad input from the person at the
// keyboard: one line naming it, status 2 (issue 18).
TEST(CameraProcess, BadSourceIsNamedAndExitsWithStatusTwo) {
  Processes procs;
  procs.start("camera", bin("ephor-camera"),
              {"/nonexistent/clip.avi", "--no-mlock", "--name", "camera"});
  ASSERT_TRUE(wait_until([&] { return !procs.exits().empty(); }, seconds(10)));
  const auto exits = procs.exits();
  EXPECT_TRUE(exits[0].failure);
  EXPECT_EQ(exits[0].code, 2);
  EXPECT_TRUE(procs.has_line("camera", "'/nonexistent/clip.avi': no such file"));
}

}  // namespace
}  // namespace ephor::testing
