// Integration test in a private network namespace (NETNS): ephor-sim and
// ephor-calibrate as real processes over LCM. The written calibration loads
// and agrees with the simulator's true camera to < 1 mm over the field in
// both planes; the arm ends parked and the light off.

#include <chrono>
#include <csignal>
#include <mutex>
#include <optional>
#include <string>

#include <gtest/gtest.h>

#include "common/arm/arm_workcell.h"
#include "common/calibration/field_calibration.h"
#include "common/lcm/bus.h"
#include "common/lcm/channels.h"
#include "ephor/joint_state_t.hpp"
#include "tests/integration/harness.h"

namespace ephor::calibrate {
namespace {

using namespace std::chrono_literals;
using calibration::Plane;
using ephor::testing::wait_until;

double worst_error_mm(const calibration::FieldCalibration& cal, Plane plane) {
  const geometry::OverheadCamera cam;
  const geometry::Workcell cell;
  const double z = plane == Plane::kObject ? cell.object_plane_z_mm : cell.elevation_plane_z_mm;
  double worst = 0.0;
  for (double x = 0.0; x <= cell.field_length_mm; x += cell.field_length_mm / 10)
    for (double y = 0.0; y <= cell.field_width_mm; y += cell.field_width_mm / 10) {
      const Eigen::Vector2d px = cam.project(x, y, z);
      worst = std::max(worst,
                       (cal.image_to_field(px.x(), px.y(), plane) - Eigen::Vector2d(x, y)).norm());
    }
  return worst;
}

TEST(CalibrateProcess, CalibratesAgainstTheRunningSimulator) {
  const std::string out = ephor::testing::write_temp_file("calibrated.pbtxt", "");
  ephor::testing::Processes procs;
  procs.start("sim", ephor::testing::bin("ephor-sim"),
              {"--sheep", "0", "--seed", "3", "--no-mlock"});
  Bus bus("", "calibrate-test");
  std::mutex mutex;
  std::optional<joint_state_t> servo;
  bus.subscribe<joint_state_t>(channels::kArmServo, [&](const joint_state_t& m) {
    std::lock_guard<std::mutex> lock(mutex);
    servo = m;
  });
  bus.start();
  ASSERT_TRUE(wait_until(
      [&] {
        std::lock_guard<std::mutex> lock(mutex);
        return servo.has_value();
      },
      10s))
      << "ephor-sim does not publish ARM_SERVO";

  procs.start(
      "calibrate", ephor::testing::bin("ephor-calibrate"),
      {"--out", out, "--speed", "0.9", "--settle-s", "0.2", "--timeout-s", "150", "--no-mlock"});
  const auto calibrate_exit = [&]() -> std::optional<launcher::ExitInfo> {
    for (const auto& e : procs.exits())
      if (e.name == "calibrate") return e;
    return std::nullopt;
  };
  ASSERT_TRUE(wait_until([&] { return calibrate_exit().has_value(); }, 170s))
      << "ephor-calibrate did not finish";
  const auto e = *calibrate_exit();
  for (const auto& line : procs.lines("calibrate")) std::printf("%s\n", line.c_str());
  ASSERT_FALSE(e.signaled);
  ASSERT_EQ(e.code, 0) << e.describe();
  EXPECT_TRUE(procs.has_line("calibrate", "rms residual"));

  const auto cal = calibration::FieldCalibration::load(out);
  EXPECT_EQ(cal.object_points().size(), 6u);
  EXPECT_EQ(cal.elevation_points().size(), 4u);
  EXPECT_LT(worst_error_mm(cal, Plane::kObject), 1.0);
  EXPECT_LT(worst_error_mm(cal, Plane::kElevation), 1.0);

  // The arm is parked and the light is off (the sim logs every change; the last one says off).
  {
    std::lock_guard<std::mutex> lock(mutex);
    const arm::Joints q = Eigen::Map<const arm::Joints>(servo->q);
    EXPECT_LT((q - arm::park_joints(geometry::Workcell{})).cwiseAbs().maxCoeff(), 2e-3);
  }
  std::string last_light;
  for (const auto& line : procs.lines("sim"))
    if (line.find("tool light") != std::string::npos) last_light = line;
  EXPECT_NE(last_light.find("tool light off"), std::string::npos) << last_light;
  bus.stop();
}

std::optional<launcher::ExitInfo> exit_of(const ephor::testing::Processes& procs,
                                          const std::string& name) {
  for (const auto& e : procs.exits())
    if (e.name == name) return e;
  return std::nullopt;
}

TEST(CalibrateProcess, SaysWhatIsMissingWhenNothingRuns) {
  ephor::testing::Processes procs;
  procs.start("probe", ephor::testing::bin("ephor-calibrate"), {"--probe-s", "0.5"});
  procs.start("calibrate", ephor::testing::bin("ephor-calibrate"),
              {"--out", ephor::testing::write_temp_file("never.pbtxt", "")});
  ASSERT_TRUE(wait_until(
      [&] {
        return exit_of(procs, "probe").has_value() && exit_of(procs, "calibrate").has_value();
      },
      20s));
  EXPECT_EQ(exit_of(procs, "probe")->code, 3);
  EXPECT_EQ(exit_of(procs, "calibrate")->code, 1);
  EXPECT_TRUE(procs.has_line("calibrate", "no servo state on ARM_SERVO within 5 s"));
}

TEST(CalibrateProcess, TurnsTheLightOffWhenInterrupted) {
  ephor::testing::Processes procs;
  procs.start("sim", ephor::testing::bin("ephor-sim"), {"--sheep", "0", "--no-mlock"});
  procs.start("calibrate", ephor::testing::bin("ephor-calibrate"),
              {"--out", ephor::testing::write_temp_file("never.pbtxt", ""), "--settle-s", "2"});
  // The first point: the light goes on (with --settle-s 2 it stays on for a while), then SIGTERM.
  ASSERT_TRUE(wait_until([&] { return procs.has_line("sim", "tool light on"); }, 60s));
  procs.signal("calibrate", SIGTERM);
  ASSERT_TRUE(wait_until([&] { return exit_of(procs, "calibrate").has_value(); }, 10s));
  EXPECT_NE(exit_of(procs, "calibrate")->code, 0);
  EXPECT_TRUE(procs.has_line("calibrate", "interrupted"));
  std::string last_light;
  EXPECT_TRUE(wait_until(
      [&] {
        for (const auto& line : procs.lines("sim"))
          if (line.find("tool light") != std::string::npos) last_light = line;
        return last_light.find("tool light off") != std::string::npos;
      },
      5s))
      << last_light;
}

}  // namespace
}  // namespace ephor::calibrate
