// The light-stripe system (deploy/stripe.pbtxt) started headless by the
// launcher, as `tools/ephor stripe scan` runs it, in a private network
// namespace:
//  - a short raster of the flat plate (9 stripes 10 mm apart) gives a cloud
//    whose points lie on a plane within the random-error target (0.3 mm 1
//    sigma; paper section 5: +-1 mm), at the plate's height, and the run
//    ends by itself;
//  - bad input (a scene file that does not parse, a region out of reach, a
//    calibration file of another robot or with a field missing) is refused
//    by `tools/ephor stripe scan` with one line naming the problem and status
//    2, and by the processes themselves when started anyway: the arm never
//    moves (no ARM_TRAJECTORY on the bus).

#include <sys/wait.h>
#include <unistd.h>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <mutex>
#include <string>

#include <gtest/gtest.h>

#include "common/lcm/bus.h"
#include "common/lcm/channels.h"
#include "common/stripe/cloud_file.h"
#include "common/stripe/plane_fit.h"
#include "common/stripe/stripe_channels.h"
#include "ephor/joint_trajectory_t.hpp"
#include "ephor/stripe_cloud_t.hpp"
#include "tests/integration/harness.h"

namespace ephor::testing {
namespace {

using std::chrono::seconds;

constexpr const char* kUrl = "udpm://239.255.76.67:7674?ttl=0&recv_buf_size=16777216";

std::string temp_dir() {
  const std::string d = ::testing::TempDir() + "stripe-scan-" + std::to_string(getpid());
  std::system(("mkdir -p " + d).c_str());
  return d;
}

TEST(StripeScan, FlatPlateGivesAPlaneWithinTheRandomErrorTarget) {
  const std::string out = temp_dir() + "/plate.ply";
  std::mutex mutex;
  std::vector<stripe_cloud_t> clouds;
  Bus bus(kUrl, "scan-test");
  bus.subscribe<stripe_cloud_t>(stripe::channels::kCloud, [&](const stripe_cloud_t& m) {
    std::lock_guard<std::mutex> lock(mutex);
    clouds.push_back(m);
  });
  bus.start();
  Processes p;
  p.start("launch", bin("ephor-launch"),
          {source_path("deploy/stripe.pbtxt"), "--headless", "--duration", "50", "--scene",
           source_path("deploy/stripe/scenes/flat_plate.obj"), "--region=-40,-30,40,30",
           "--step_mm", "10", "--out", out},
          {{"LCM_DEFAULT_URL", kUrl}});
  ASSERT_TRUE(wait_until([&] { return p.exited("launch"); }, seconds(55)))
      << "the scan did not end";
  bus.stop();
  EXPECT_EQ(p.exits().front().code, 0) << "the launcher reported a failed process";
  EXPECT_TRUE(p.has_line("launch", "planner finished"));
  {
    std::lock_guard<std::mutex> lock(mutex);
    ASSERT_FALSE(clouds.empty()) << "no STRIPE_CLOUD";
    EXPECT_EQ(clouds.back().stripes, 9);
    EXPECT_EQ(clouds.back().stripes_missing, 0);
  }
  const auto cloud = stripe::load_cloud_ply(out);
  ASSERT_GT(cloud.size(), 9u * 200u) << "points in " << out;
  const auto fit = stripe::PlaneFit::fit(cloud);
  ASSERT_TRUE(fit);
  std::fprintf(stderr, "flat plate: %zu points, 1 sigma %.4f mm, max %.4f mm, height %.3f mm\n",
               cloud.size(), fit->rms_mm, fit->max_abs_mm, fit->centroid.z());
  EXPECT_LT(fit->rms_mm, 0.3) << "the random-error target";
  EXPECT_GT(std::abs(fit->normal.z()), 0.999) << "the plate is level";
  EXPECT_NEAR(fit->centroid.z(), 20.0, 1.0)
      << "the plate's top (deploy/stripe/scenes/flat_plate.obj)";
}

struct ToolRun {
  int code = -1;
  std::string err;
};

ToolRun run_tool(const std::string& args) {
  const std::string err_file = temp_dir() + "/err.txt";
  const std::string cmd = "EPHOR_BIN=" + std::string(std::getenv("EPHOR_BIN_DIR")) + " " +
                          source_path("tools/ephor.d/stripe") + " " + args + " >/dev/null 2>" +
                          err_file;
  const int status = std::system(cmd.c_str());
  ToolRun r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  if (std::FILE* f = std::fopen(err_file.c_str(), "rb")) {
    char buf[4096];
    size_t n = 0;
    while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) r.err.append(buf, n);
    std::fclose(f);
  }
  return r;
}

TEST(StripeScan, BadInputIsOneLineStatusTwoAndTheArmNeverMoves) {
  std::atomic<int> trajectories{0};
  Bus bus(kUrl, "scan-test");
  bus.subscribe<joint_trajectory_t>(ephor::channels::kArmTrajectory,
                                    [&](const joint_trajectory_t&) { ++trajectories; });
  bus.start();
  const std::string dir = temp_dir();
  const std::string plate = source_path("deploy/stripe/scenes/flat_plate.obj");
  const std::string bad_obj = dir + "/bad.obj";
  std::ofstream(bad_obj) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n";
  // A calibration file of robot seed 2, and the same without its camera.
  const std::string other = dir + "/seed2.pbtxt";
  const std::string missing = dir + "/missing.pbtxt";
  {
    const std::string text =
        "zero_offset_deg: [0, 0.1, 0.2, 0.3, 0.4, 0]\n"
        "camera_in_flange { translation_mm: [120, 0, 60] quaternion_wxyz: [1, 0, 0, 0] }\n"
        "projector_in_flange { translation_mm: [0, 0, 80] quaternion_wxyz: [1, 0, 0, 0] }\n";
    std::ofstream(other) << "robot_seed: 2\n"
                         << text
                         << "camera { width_px: 256 height_px: 256 fx_px: 625 fy_px: 625 cx_px: "
                            "127.5 cy_px: 127.5 }\n";
    std::ofstream(missing) << "robot_seed: 5\n" << text;
  }
  const std::string out = " --out " + dir + "/x.ply";
  struct Case {
    std::string args, names;
  } cases[] = {
      {"--scene " + bad_obj + " --region=-10,-10,10,10" + out, "line 4"},
      {"--scene " + plate + " --region=-50,-50,50,700" + out,
       "region corner (x1, y1) = (50, 700) mm"},
      {"--scene " + plate + " --region=-50,-50,50,50 --robot-seed 5 --calibration " + other + out,
       "measured on robot seed 2, this robot is seed 5"},
      {"--scene " + plate + " --region=-50,-50,50,50 --robot-seed 5 --calibration " + missing + out,
       "camera: missing"},
  };
  for (const Case& c : cases) {
    const ToolRun r = run_tool("scan " + c.args);
    EXPECT_EQ(r.code, 2) << c.args << "\n" << r.err;
    EXPECT_NE(r.err.find(c.names), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "one line: " << r.err;
  }
  // The processes refuse the same by themselves (started anyway, past the
  // tool's checks): the run ends at once and nothing moves.
  Processes p;
  p.start("launch", bin("ephor-launch"),
          {source_path("deploy/stripe.pbtxt"), "--headless", "--duration", "20", "--scene", plate,
           "--region=-50,-50,50,50", "--robot_seed", "5", "--calibration", other},
          {{"LCM_DEFAULT_URL", kUrl}});
  ASSERT_TRUE(wait_until([&] { return p.exited("launch"); }, seconds(25)));
  EXPECT_NE(p.exits().front().code, 0);
  EXPECT_TRUE(p.has_line("launch", "measured on robot seed 2, this robot is seed 5"));
  bus.stop();
  EXPECT_EQ(trajectories.load(), 0) << "the arm was sent a trajectory";
}

}  // namespace
}  // namespace ephor::testing
