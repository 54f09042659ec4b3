// The whole catching system (deploy/catch.pbtxt) started headless by the
// launcher, as a user runs it, in a private network namespace; scored by
// ephor-catch-monitor's summary against the simulator's ground truth.
//
// What every run must give: the run ends by itself after its balls, each
// ball judged; the camera's pose found from the circles; a world-model
// output for every frame; the ball placed on the board within a few mm; the
// arm sent goals. It does not assert catches: the system does not yet catch
// most of the balls an arm could (README.md, "Ball catching"; the rate over
// many balls is `tools/ephor bench catch`), and a test that fails on some
// runs would teach people to ignore it.

#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/integration/harness.h"

namespace ephor::testing {
namespace {

using std::chrono::seconds;

TEST(Catch, HeadlessRunOfThreeBallsTracksAndScoresThem) {
  const std::string summary = write_temp_file("summary.json", "");
  Processes p;
  p.start("launch", bin("ephor-launch"),
          {source_path("deploy/catch.pbtxt"), "--headless", "--duration", "60", "--balls", "3",
           "--seed", "2", "--summary", summary});
  ASSERT_TRUE(wait_until(
      [&] {
        for (const auto& e : p.exits())
          if (e.name == "launch") return true;
        return false;
      },
      seconds(90)));
  ASSERT_EQ(p.exits().front().code, 0) << "the launcher reported a failed process";

  nlohmann::json s;
  std::ifstream(summary) >> s;
  std::fprintf(stderr, "summary: %s\n", s.dump().c_str());
  EXPECT_EQ(s["scenario"], "catch");
  EXPECT_EQ(s["balls"], 3) << "the run ended before three balls were judged";
  EXPECT_EQ(s["missed"].size() + static_cast<size_t>(s["caught"].get<int>()), 3u);
  ASSERT_FALSE(s["camera_pose_error_mm"].is_null()) << "no camera pose from the circles";
  EXPECT_LT(s["camera_pose_error_mm"].get<double>(), 1.0);
  EXPECT_LT(s["camera_pose_error_deg"].get<double>(), 0.1);
  EXPECT_GE(s["tasks"]["arm/command"]["jobs"].get<int>(), 1) << "the arm was never sent a goal";
  EXPECT_GT(s["world_outputs"].get<int>(), 100);
  EXPECT_LT(s["update_ms"]["p50"].get<double>(), 17.5) << "not a world-model output per frame";
  EXPECT_LT(s["position_error_mm"]["p50"].get<double>(), 5.0);
}

}  // namespace
}  // namespace ephor::testing
