// The whole shepherding system (deploy/shepherd.pbtxt) started headless by
// the launcher, as a user runs it, in a private network namespace; scored by
// ephor-monitor's summary against the simulator's ground truth.
//
// What it asserts is what every run must give: all processes up for the
// whole run, vision at camera rate, tracks without id switches and within
// 1 px, the arm sent and the sheep turned back at least once. It does not
// assert zero escapes: the system does not yet keep every sheep on the field
// in every run (issue 3; escapes per run are measured with the headless
// runs in README.md), and a test that fails on one run in three would teach
// people to ignore it.

#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/integration/harness.h"

namespace ephor::testing {
namespace {

using std::chrono::seconds;

TEST(Shepherd, HeadlessRunTracksOneSheepAndTurnsItBack) {
  const std::string summary = write_temp_file("summary.json", "");
  Processes p;
  p.start("launch", bin("ephor-launch"),
          {source_path("deploy/shepherd.pbtxt"), "--headless", "--duration", "40", "--seed", "7",
           "--sheep", "1", "--summary", summary});
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
  EXPECT_EQ(s["sheep"], 1);
  EXPECT_GE(s["saves"].get<int>(), 1) << "the arm never turned the sheep back";
  EXPECT_EQ(s["id_switches"], 0);
  EXPECT_GE(s["vision_rate_hz"].get<double>(), 25.0);
  EXPECT_GE(s["arm_commands"].get<int>(), 1);  // the arm was sent somewhere
  EXPECT_LT(s["position_error_px_rms"].get<double>(), 1.0);
  EXPECT_TRUE(s["scheduler_seen"].get<bool>());
  EXPECT_GT(s["duration_s"].get<double>(), 35.0);
}

}  // namespace
}  // namespace ephor::testing
