// End-to-end check of ephor-vision on the simulator's camera: ephor-sim and
// ephor-vision run as real processes (NETNS: a private network namespace);
// every BLOBS message is matched by frame index with the GROUND_TRUTH of the
// same frame, and the blobs are scored against the true mark centres.

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdlib>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "common/lcm/bus.h"
#include "common/lcm/channels.h"
#include "ephor/shepherd_blobs_t.hpp"
#include "ephor/shepherd_ground_truth_t.hpp"
#include "procs/shepherd/vision/test_child_process.h"

namespace ephor::vision {
namespace {

using namespace std::chrono_literals;

std::string test_lcm_url() {
  const char* in_netns = std::getenv("EPHOR_IN_NETNS");
  if (in_netns != nullptr && std::string(in_netns) == "1") return resolve_lcm_url("");
  const int port = 20000 + static_cast<int>((getpid() + 7) % 20000);
  return "udpm://239.255.76.67:" + std::to_string(port) + "?ttl=0&recv_buf_size=16777216";
}

std::string log_path(const std::string& who) {
  const std::string test = ::testing::UnitTest::GetInstance()->current_test_info()->name();
  std::string name = "vision_sim_test_" + who + "_" + std::to_string(getpid()) + "_" + test;
  for (char& c : name) c = c == '/' ? '_' : c;
  return ::testing::TempDir() + name + ".log";
}

struct Variant {
  std::string mode;  // --mode
  std::string scan;  // --scan
};

class VisionSimTest : public ::testing::TestWithParam<Variant> {};

TEST_P(VisionSimTest, BlobsMatchTheSimulatorsMarks) {
  const Variant variant = GetParam();
  const std::string url = test_lcm_url();
  Bus bus(url, "test");
  std::mutex mutex;
  std::condition_variable cv;
  std::map<int64_t, shepherd_ground_truth_t> truth;
  std::map<int64_t, shepherd_blobs_t> blobs;
  bus.subscribe<shepherd_ground_truth_t>(channels::kGroundTruth,
                                         [&](const shepherd_ground_truth_t& m) {
                                           std::lock_guard<std::mutex> lock(mutex);
                                           truth[m.frame_index] = m;
                                         });
  bus.subscribe<shepherd_blobs_t>(channels::kBlobs, [&](const shepherd_blobs_t& m) {
    {
      std::lock_guard<std::mutex> lock(mutex);
      blobs[m.frame_index] = m;
    }
    cv.notify_all();
  });
  bus.start();
  const std::vector<std::string> sim_args = {"--name",     "sim",       "--sheep", "6",
                                             "--seed",     "3",         "--host",  "test",
                                             "--no-mlock", "--lcm-url", url};
  const std::vector<std::string> vision_args = {"--name",     "vision",    "--host", "test",
                                                "--no-mlock", "--lcm-url", url};
  TestChildProcess sim("ephor-sim", sim_args, log_path("sim"));
  TestChildProcess vision("ephor-vision", vision_args, log_path("vision"));

  // Three seconds of frames (about 90 at 30 Hz) that have both.
  const auto scored = [&] {
    int n = 0;
    for (const auto& [index, b] : blobs) n += truth.count(index) ? 1 : 0;
    return n;
  };
  {
    std::unique_lock<std::mutex> lock(mutex);
    ASSERT_TRUE(cv.wait_for(lock, 30s, [&] { return scored() >= 90; }))
        << "only " << scored() << " frames with BLOBS and GROUND_TRUTH; vision log:\n"
        << vision.log() << "\nsim log:\n"
        << sim.log();
  }
  bus.stop();
  EXPECT_EQ(vision.stop(), "") << vision.log();
  EXPECT_EQ(sim.stop(), "") << sim.log();

  // A partly hidden mark (under the arm, or at the image edge) gives a blob
  // at the centroid of its visible part, which is where it should be but not
  // the mark's centre: such blobs are matched (within 10 px) but only whole
  // marks (blob area >= 150 px; a whole mark is about 172 px) are scored.
  const bool dump = std::getenv("VISION_SIM_TEST_DUMP") != nullptr;
  int frames = 0, visible = 0, found = 0, whole = 0, extra = 0;
  double sum_sq = 0.0, sum_du = 0.0, sum_dv = 0.0;
  for (const auto& [index, b] : blobs) {
    const auto t = truth.find(index);
    if (t == truth.end()) continue;
    ++frames;
    EXPECT_EQ(b.utime, t->second.utime) << "frame " << index;
    std::vector<bool> used(b.blobs.size(), false);
    for (const shepherd_sheep_truth_t& s : t->second.sheep) {
      int best = -1;
      double best_d2 = 100.0;
      for (size_t i = 0; i < b.blobs.size(); ++i) {
        const double du = static_cast<double>(b.blobs[i].u - s.u);
        const double dv = static_cast<double>(b.blobs[i].v - s.v);
        if (!used[i] && du * du + dv * dv < best_d2) {
          best_d2 = du * du + dv * dv;
          best = static_cast<int>(i);
        }
      }
      if (best >= 0) used[static_cast<size_t>(best)] = true;
      const bool inside = s.u >= 12 && s.v >= 12 && s.u <= 500 && s.v <= 470;
      if (!s.visible || !s.on_field || !inside) continue;
      ++visible;
      if (best < 0) {
        if (dump) std::printf("frame %lld sheep %d missed\n", static_cast<long long>(index), s.id);
        continue;
      }
      ++found;
      const shepherd_blob_t& bl = b.blobs[static_cast<size_t>(best)];
      if (dump) {
        std::printf("frame %lld sheep %d truth %.3f %.3f blob %.3f %.3f area %d\n",
                    static_cast<long long>(index), s.id, static_cast<double>(s.u),
                    static_cast<double>(s.v), static_cast<double>(bl.u), static_cast<double>(bl.v),
                    bl.area);
      }
      if (bl.area < 150) continue;
      ++whole;
      sum_sq += best_d2;
      sum_du += static_cast<double>(bl.u - s.u);
      sum_dv += static_cast<double>(bl.v - s.v);
    }
    for (size_t i = 0; i < used.size(); ++i) {
      if (used[i]) continue;
      ++extra;
      std::printf("frame %lld: blob at (%.1f, %.1f), area %d, is no sheep's mark\n",
                  static_cast<long long>(index), static_cast<double>(b.blobs[i].u),
                  static_cast<double>(b.blobs[i].v), b.blobs[i].area);
    }
  }
  ASSERT_GT(whole, 0);
  const double rms = std::sqrt(sum_sq / whole);
  std::printf(
      "%s/%s, %d frames: %d visible marks, %d found, %d whole; %d blobs of no mark; whole-mark "
      "centroid "
      "rms %.3f px, mean error (%.3f, %.3f) px\n",
      variant.mode.c_str(), variant.scan.c_str(), frames, visible, found, whole, extra, rms,
      sum_du / whole, sum_dv / whole);
  EXPECT_EQ(found, visible);
  EXPECT_EQ(extra, 0);
  EXPECT_GE(whole, visible * 8 / 10);
  EXPECT_LE(rms, 0.25);
}

INSTANTIATE_TEST_SUITE_P(Modes, VisionSimTest,
                         ::testing::Values(Variant{"blobify", "full"}, Variant{"trackify", "full"},
                                           Variant{"blobify", "axis"}),
                         [](const ::testing::TestParamInfo<Variant>& p) {
                           return p.param.mode + "_" + p.param.scan;
                         });

}  // namespace
}  // namespace ephor::vision
