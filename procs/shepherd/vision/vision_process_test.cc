// Integration test of ephor-vision as a real process: this test plays the
// camera and the display over LCM and reads BLOBS. Registered with NETNS (a
// private network namespace, default LCM URL); run plainly it uses a private
// port so it cannot hear other LCM traffic on the host.

#include <unistd.h>

#include <chrono>
#include <condition_variable>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <memory>
#include <mutex>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "common/lcm/bus.h"
#include "common/lcm/channels.h"
#include "common/runtime/channels.h"
#include "common/shepherd/vision/synthetic_image.h"
#include "common/time/clock.h"
#include "ephor/camera_frame_t.hpp"
#include "ephor/shepherd_blobs_t.hpp"
#include "ephor/shepherd_vision_cmd_t.hpp"
#include "ephor/task_register_t.hpp"
#include "procs/shepherd/vision/test_child_process.h"

namespace ephor::vision {
namespace {

using namespace std::chrono_literals;

constexpr int8_t kModeBlobify = shepherd_vision_cmd_t::MODE_BLOBIFY;
constexpr int8_t kModeTrackify = shepherd_vision_cmd_t::MODE_TRACKIFY;

std::string test_lcm_url() {
  const char* in_netns = std::getenv("EPHOR_IN_NETNS");
  if (in_netns != nullptr && std::string(in_netns) == "1") return resolve_lcm_url("");
  const int port = 20000 + static_cast<int>(getpid() % 20000);
  return "udpm://239.255.76.67:" + std::to_string(port) + "?ttl=0&recv_buf_size=16777216";
}

class VisionProcessTest : public ::testing::Test {
 protected:
  void SetUp() override {
    url_ = test_lcm_url();
    bus_ = std::make_unique<Bus>(url_, "test");
    bus_->subscribe<shepherd_blobs_t>(channels::kBlobs, [this](const shepherd_blobs_t& m) {
      update([&] { blobs_.push_back(m); });
    });
    bus_->subscribe<task_register_t>(channels::kTaskRegister, [this](const task_register_t& m) {
      if (m.process == "vision" && m.task == "vision") update([&] { ready_ = true; });
    });
    bus_->start();
    vision_ = std::make_unique<TestChildProcess>(
        "ephor-vision",
        std::vector<std::string>{"--name", "vision", "--host", "test", "--no-mlock", "--lcm-url",
                                 url_, "--period-ms", "10"},
        ::testing::TempDir() + "vision_process_test_" + std::to_string(getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".log");
    ASSERT_TRUE(wait([this] { return ready_; }, 10s))
        << "ephor-vision did not register its task within 10 s; log:\n"
        << log();
  }

  void TearDown() override {
    if (vision_) {
      const std::string outcome = vision_->stop();
      EXPECT_EQ(outcome, "") << "ephor-vision: " << outcome << "; log:\n" << log();
    }
    if (bus_) bus_->stop();
  }

  template <class F>
  void update(F&& f) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      f();
    }
    cv_.notify_all();
  }
  bool wait(const std::function<bool()>& pred, std::chrono::milliseconds timeout) {
    std::unique_lock<std::mutex> lock(mutex_);
    return cv_.wait_for(lock, timeout, pred);
  }
  std::vector<shepherd_blobs_t> received() {
    std::lock_guard<std::mutex> lock(mutex_);
    return blobs_;
  }

  bool wait_log(const std::string& text, std::chrono::milliseconds timeout) const {
    return vision_->wait_log(text, timeout);
  }
  std::string log() const { return vision_->log(); }

  // A 512 x 482 frame with marks at `centres`.
  camera_frame_t frame(int64_t index, std::initializer_list<std::pair<double, double>> centres) {
    img_.fill(40.0f);
    for (const auto& [u, v] : centres) img_.add_disc(u, v, 8.0, 200.0f);
    img_.render(3.0, rng_);
    camera_frame_t f{};
    f.utime = 1'000'000 + index * 33'333;
    f.frame_index = index;
    f.width = img_.width();
    f.height = img_.height();
    f.size = f.width * f.height;
    f.data.assign(img_.pixels().begin(), img_.pixels().end());
    return f;
  }

  void command(bool paused, int8_t mode, int32_t threshold) {
    shepherd_vision_cmd_t c{};
    c.utime = wall_us();
    c.paused = paused;
    c.mode = mode;
    c.scan = shepherd_vision_cmd_t::SCAN_FULL;
    c.threshold = threshold;
    bus_->publish(channels::kVisionCmd, c);
  }

  // Publishes frames (a camera's pace, 20 ms) until `pred` holds or `timeout`.
  bool stream_until(int64_t& index, std::initializer_list<std::pair<double, double>> centres,
                    const std::function<bool()>& pred, std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < deadline) {
      camera_frame_t f = frame(index++, centres);
      bus_->publish(channels::kCamera, f);
      if (wait(pred, 20ms)) return true;
    }
    return false;
  }

  std::string url_;
  std::unique_ptr<Bus> bus_;
  std::mutex mutex_;
  std::condition_variable cv_;
  std::vector<shepherd_blobs_t> blobs_;
  bool ready_ = false;
  std::unique_ptr<TestChildProcess> vision_;
  SyntheticImage img_{512, 482, 40.0f};
  std::mt19937 rng_{17};
};

TEST_F(VisionProcessTest, PublishesBlobsOfEachFrameWithItsCaptureTime) {
  int64_t index = 0;
  ASSERT_TRUE(stream_until(
      index, {{100.3, 200.7}, {400.0, 100.0}}, [this] { return !blobs_.empty(); }, 5s))
      << "no BLOBS; log:\n"
      << log();
  const shepherd_blobs_t b = received().front();
  EXPECT_EQ(b.utime, 1'000'000 + b.frame_index * 33'333);
  EXPECT_EQ(b.mode, kModeBlobify);
  EXPECT_NEAR(b.threshold, 176, 3);
  EXPECT_GT(b.processing_us, 0.0f);
  ASSERT_EQ(b.num_blobs, 2);
  ASSERT_EQ(b.blobs.size(), 2u);
  const shepherd_blob_t& first = b.blobs[0].u < b.blobs[1].u ? b.blobs[0] : b.blobs[1];
  EXPECT_NEAR(first.u, 100.3, 0.3);
  EXPECT_NEAR(first.v, 200.7, 0.3);
  EXPECT_NEAR(first.area, 190, 30);
}

TEST_F(VisionProcessTest, SkipsBadFramesAndFollowsCommands) {
  int64_t index = 0;
  ASSERT_TRUE(stream_until(
      index, {{100.0, 200.0}}, [this] { return !blobs_.empty(); }, 5s))
      << log();
  // A frame whose size field disagrees with its dimensions is counted, logged
  // and skipped; the process goes on.
  camera_frame_t bad = frame(index++, {{100.0, 200.0}});
  bad.width = 100;
  bus_->publish(channels::kCamera, bad);
  ASSERT_TRUE(wait_log("skipping bad camera frame", 5s)) << log();
  // An invalid command is logged and ignored (blobify goes on).
  command(false, 9, -1);
  ASSERT_TRUE(wait_log("mode 9", 5s)) << log();
  const int64_t after_bad = index;
  ASSERT_TRUE(stream_until(
      index, {{100.0, 200.0}},
      [&] { return !blobs_.empty() && blobs_.back().frame_index >= after_bad; }, 5s))
      << log();
  EXPECT_EQ(received().back().mode, kModeBlobify);
  for (const shepherd_blobs_t& b : received()) EXPECT_NE(b.frame_index, bad.frame_index);

  // Paused: frames keep coming, no BLOBS go out.
  command(true, kModeBlobify, -1);
  ASSERT_TRUE(wait_log("vision mode: paused", 5s)) << log();
  const int64_t paused_from = index;
  EXPECT_FALSE(stream_until(
      index, {{100.0, 200.0}},
      [&] { return !blobs_.empty() && blobs_.back().frame_index >= paused_from; }, 300ms))
      << "BLOBS published while paused";

  // Resumed in trackify with a fixed threshold.
  command(false, kModeTrackify, 150);
  ASSERT_TRUE(stream_until(
      index, {{101.0, 200.0}},
      [this] {
        return !blobs_.empty() && blobs_.back().mode == kModeTrackify &&
               blobs_.back().blobs.size() == 1 && blobs_.back().blobs[0].u > 100.5f;
      },
      5s))
      << log();
  const shepherd_blobs_t last = received().back();
  EXPECT_EQ(last.threshold, 150);
  EXPECT_NEAR(last.blobs[0].u, 101.0, 0.3);
  EXPECT_NEAR(last.blobs[0].v, 200.0, 0.3);
}

}  // namespace
}  // namespace ephor::vision
