#include "procs/shepherd/sim/sim_config.h"

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "common/config/text_proto.h"

namespace ephor::sim {
namespace {

std::string write_file(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + name;
  std::ofstream(path) << text;
  return path;
}

TEST(SimConfig, FileOverridesOnlyTheFieldsItSets) {
  SimulatorConfig c;
  double fps = 30.0;
  apply_config_file(write_file("sim_ok.pbtxt",
                               "sheep: 6\nseed: 11\nspeed_mm_s: 45\nfps: 20\n"
                               "noise_sigma: 0\nreentry_s: -1\n"),
                    c, fps);
  EXPECT_EQ(c.world.sheep, 6);
  EXPECT_EQ(c.world.seed, 11u);
  EXPECT_EQ(c.world.speed_mm_s, 45.0);
  EXPECT_EQ(c.world.reentry_s, -1.0);
  EXPECT_EQ(c.camera.noise_sigma, 0.0);
  EXPECT_EQ(fps, 20.0);
  EXPECT_EQ(c.world.speed_spread, 0.2);  // untouched default
}

TEST(SimConfig, ExampleFileLoads) {
  const char* src = std::getenv("EPHOR_SOURCE_DIR");
  if (src == nullptr) GTEST_SKIP() << "EPHOR_SOURCE_DIR not set (run through ctest)";
  SimulatorConfig c;
  double fps = 0.0;
  apply_config_file(std::string(src) + "/procs/shepherd/sim/sim.example.pbtxt", c, fps);
  EXPECT_EQ(c.world.sheep, 6);
  EXPECT_EQ(fps, 30.0);
}

TEST(SimConfig, BadFilesAreReportedWithTheFileAndProblem) {
  SimulatorConfig c;
  double fps = 30.0;
  const std::string unknown = write_file("sim_unknown.pbtxt", "sheep: 2\nsheeps: 3\n");
  try {
    apply_config_file(unknown, c, fps);
    FAIL() << "unknown field accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find(unknown + ":2"), std::string::npos) << e.what();
  }
  const std::string bad_fps = write_file("sim_fps.pbtxt", "fps: 0\n");
  EXPECT_THROW(apply_config_file(bad_fps, c, fps), ConfigError);
  const std::string bad_speed = write_file("sim_speed.pbtxt", "speed_spread: 1.5\n");
  try {
    apply_config_file(bad_speed, c, fps);
    FAIL() << "speed_spread 1.5 accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("speed_spread"), std::string::npos) << e.what();
  }
  EXPECT_THROW(apply_config_file("/nonexistent/sim.pbtxt", c, fps), ConfigError);
}

}  // namespace
}  // namespace ephor::sim
