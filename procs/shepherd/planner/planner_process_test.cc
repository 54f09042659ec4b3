// ephor-planner as a process, in a private network namespace: objects in on
// OBJECTS, one arm goal at a time out on ARM_GOAL in image coordinates (with
// the capture time of the objects it came from), the next goal only after
// MOTION_DONE; garbage on its inputs does not stop it.

#include <cmath>
#include <mutex>
#include <optional>
#include <vector>

#include <gtest/gtest.h>

#include "common/calibration/field_calibration.h"
#include "common/lcm/bus.h"
#include "common/lcm/channels.h"
#include "ephor/arm_goal_t.hpp"
#include "ephor/arm_state_t.hpp"
#include "ephor/motion_done_t.hpp"
#include "ephor/shepherd_objects_t.hpp"
#include "ephor/shepherd_planner_cmd_t.hpp"
#include "ephor/shepherd_planner_status_t.hpp"
#include "tests/integration/harness.h"

namespace ephor::testing {
namespace {

using std::chrono::seconds;

class Probe {
 public:
  Probe() : bus_("", "probe") {
    bus_.subscribe<arm_goal_t>(channels::kArmGoal, [this](const arm_goal_t& m) {
      std::lock_guard<std::mutex> lock(mutex_);
      goals_.push_back(m);
    });
    bus_.subscribe<shepherd_planner_status_t>(channels::kPlannerStatus,
                                              [this](const shepherd_planner_status_t& m) {
                                                std::lock_guard<std::mutex> lock(mutex_);
                                                status_ = m;
                                              });
    bus_.start();
  }
  std::vector<arm_goal_t> goals() {
    std::lock_guard<std::mutex> lock(mutex_);
    return goals_;
  }
  std::optional<shepherd_planner_status_t> status() {
    std::lock_guard<std::mutex> lock(mutex_);
    return status_;
  }
  Bus& bus() { return bus_; }

 private:
  Bus bus_;
  std::mutex mutex_;
  std::vector<arm_goal_t> goals_;
  std::optional<shepherd_planner_status_t> status_;
};

// One sheep at (x, y) mm walking -x at 30 mm/s: it leaves over the left edge.
shepherd_objects_t objects(int64_t utime, double x, double y) {
  shepherd_objects_t m{};
  m.utime = utime;
  shepherd_object_t o{};
  o.id = 42;
  o.state = shepherd_object_t::STATE_VISIBLE;
  o.x_mm = static_cast<float>(x);
  o.y_mm = static_cast<float>(y);
  o.vx_mm_s = -30.0f;
  o.vy_mm_s = 0.0f;
  m.objects.push_back(o);
  m.num_objects = 1;
  return m;
}

arm_state_t arm_at(double x, double y, double z) {
  arm_state_t m{};
  m.x_mm = static_cast<float>(x);
  m.y_mm = static_cast<float>(y);
  m.z_mm = static_cast<float>(z);
  m.plane = -1;
  return m;
}

TEST(PlannerProcess, SendsOneGoalAtATimeInImageCoordinates) {
  const auto calibration =
      calibration::FieldCalibration::load(source_path("deploy/calibration/sim.pbtxt"));
  Probe probe;
  Processes procs;
  procs.start("planner", bin("ephor-planner"), {"--no-mlock", "--planner", "multi"},
              {{"EPHOR_PROCESS", "planner"}, {"EPHOR_HOST", "testhost"}});
  int64_t utime = 1'000'000;
  // Up when it answers objects with a goal (republish until it does).
  ASSERT_TRUE(wait_until(
      [&] {
        auto arm = arm_at(1159, 60, 200);
        probe.bus().publish(channels::kArmState, arm);
        auto m = objects(utime, 400, 600);
        probe.bus().publish(channels::kObjects, m);
        return !probe.goals().empty();
      },
      seconds(15)))
      << "no ARM_GOAL from ephor-planner";
  const arm_goal_t first = probe.goals().front();
  EXPECT_EQ(static_cast<int>(first.plane), static_cast<int>(arm_goal_t::PLANE_ELEVATION));
  EXPECT_EQ(first.target_object, 42);
  EXPECT_EQ(first.source_frame_utime, utime);
  const Eigen::Vector2d f = calibration.image_to_field(
      static_cast<double>(first.u), static_cast<double>(first.v), calibration::Plane::kElevation);
  EXPECT_NEAR(f.y(), 600.0, 1.0);  // on the sheep's path, ahead of it
  EXPECT_LT(f.x(), 400.0);
  EXPECT_GT(f.x(), 0.0);

  // More objects, no motion_done: still one goal.
  for (int i = 1; i <= 5; ++i) {
    auto m = objects(utime + i * 33'333, 400 - i, 600);
    probe.bus().publish(channels::kObjects, m);
  }
  ASSERT_TRUE(wait_until([&] { return probe.status().has_value(); }, seconds(5)));
  EXPECT_EQ(probe.status()->planner, "multi");
  EXPECT_EQ(probe.status()->phase, "moving");
  EXPECT_EQ(probe.goals().size(), 1u);

  // Garbage on the inputs is counted, not fatal.
  const uint8_t garbage[] = {9, 9, 9};
  probe.bus().publish_raw(channels::kObjects, garbage, sizeof garbage);
  probe.bus().publish_raw(channels::kMotionDone, garbage, sizeof garbage);

  // The arm got there: motion_done, then the next frame's objects, release
  // the next goal (lowering), planned from a frame newer than the motion.
  auto arm = arm_at(f.x(), f.y(), 200);
  probe.bus().publish(channels::kArmState, arm);
  const int64_t after_motion_utime = utime + 100 * 33'333;
  ASSERT_TRUE(wait_until(
      [&] {
        motion_done_t done{};
        done.goal_id = first.goal_id;
        done.status = motion_done_t::STATUS_DONE;
        probe.bus().publish(channels::kMotionDone, done);
        auto s = arm_at(f.x(), f.y(), 200);
        probe.bus().publish(channels::kArmState, s);
        auto m = objects(after_motion_utime, 395, 600);
        probe.bus().publish(channels::kObjects, m);
        return probe.goals().size() >= 2;
      },
      seconds(10)))
      << "no second goal after motion_done";
  const arm_goal_t second = probe.goals()[1];
  EXPECT_GT(second.goal_id, first.goal_id);
  EXPECT_EQ(second.source_frame_utime, after_motion_utime);
  EXPECT_EQ(static_cast<int>(second.plane), static_cast<int>(arm_goal_t::PLANE_OBJECT));
  EXPECT_EQ(second.target_object, 42);
  EXPECT_TRUE(procs.exits().empty()) << "ephor-planner exited";
}

// The display's planner buttons: PLANNER_CMD switches the planner at run
// time; an unknown kind is refused and the planner keeps running.
TEST(PlannerProcess, SwitchesPlannerOnPlannerCmd) {
  Probe probe;
  Processes procs;
  procs.start("planner", bin("ephor-planner"), {"--no-mlock", "--planner", "multi"},
              {{"EPHOR_PROCESS", "planner"}, {"EPHOR_HOST", "testhost"}});
  int64_t utime = 1'000'000;
  const auto status_is = [&](const std::string& kind) {
    auto m = objects(utime += 33'333, 400, 600);
    probe.bus().publish(channels::kObjects, m);
    const auto s = probe.status();
    return s && s->planner == kind;
  };
  ASSERT_TRUE(wait_until([&] { return status_is("multi"); }, seconds(15)));

  shepherd_planner_cmd_t bad{};
  bad.planner = "telepathy";
  probe.bus().publish(channels::kPlannerCmd, bad);
  shepherd_planner_cmd_t cmd{};
  cmd.planner = "lookahead";
  ASSERT_TRUE(wait_until(
      [&] {
        probe.bus().publish(channels::kPlannerCmd, cmd);
        return status_is("lookahead");
      },
      seconds(10)))
      << "PLANNER_CMD did not switch the planner";
  // Goals of the new planner never reuse an id the old one may have sent.
  EXPECT_TRUE(wait_until(
      [&] {
        status_is("lookahead");  // keeps objects coming
        const auto goals = probe.goals();
        return !goals.empty() && goals.back().goal_id > 1'000'000;
      },
      seconds(10)))
      << "no goal from the new planner with an id above the old planner's";
  EXPECT_TRUE(procs.exits().empty()) << "ephor-planner exited";
}

// Issue 13: an arm serving another work cell (its elevation plane 50 mm
// lower) is noticed from ARM_STATE: the planner says so once and sends no
// goals, instead of resending them forever; when the arm rests on the
// planner's plane again, planning resumes.
TEST(PlannerProcess, StopsPlanningWhileTheArmServesAnotherWorkcell) {
  Probe probe;
  Processes procs;
  procs.start("planner", bin("ephor-planner"),
              {"--no-mlock", "--planner", "multi", "--workcell", "deploy/shepherd/workcell.pbtxt"},
              {{"EPHOR_PROCESS", "planner"}, {"EPHOR_HOST", "testhost"}});
  int64_t utime = 1'000'000;
  auto low = arm_at(1159, 60, 150);  // at rest "on the elevation plane", 50 mm low
  low.plane = arm_goal_t::PLANE_ELEVATION;
  const std::string said = "work cell disagreement";
  ASSERT_TRUE(wait_until(
      [&] {
        probe.bus().publish(channels::kArmState, low);
        auto m = objects(utime += 33'333, 400, 600);
        probe.bus().publish(channels::kObjects, m);
        return procs.has_line("planner", said);
      },
      seconds(15)))
      << "ephor-planner did not report the disagreement";
  // Two seconds of frames and arm states, each answered by a status saying
  // why there is no goal (a goal would have gone out at the first frame).
  for (int i = 0; i < 60; ++i) {
    probe.bus().publish(channels::kArmState, low);
    auto m = objects(utime += 33'333, 400, 600);
    probe.bus().publish(channels::kObjects, m);
  }
  ASSERT_TRUE(wait_until(
      [&] {
        const auto st = probe.status();
        return st && st->utime == utime;
      },
      seconds(5)));
  EXPECT_EQ(probe.status()->phase, "workcell mismatch");
  EXPECT_TRUE(probe.goals().empty());
  int reports = 0;
  for (const auto& line : procs.lines("planner")) reports += line.find(said) != std::string::npos;
  EXPECT_EQ(reports, 1) << "the disagreement is said once, not at the frame rate";

  auto right = arm_at(1159, 60, 200);
  right.plane = arm_goal_t::PLANE_ELEVATION;
  EXPECT_TRUE(wait_until(
      [&] {
        probe.bus().publish(channels::kArmState, right);
        auto m = objects(utime += 33'333, 400, 600);
        probe.bus().publish(channels::kObjects, m);
        return !probe.goals().empty();
      },
      seconds(10)))
      << "planning did not resume once the arm agreed";
  // The log line comes through the output pipe, after the goal maybe.
  EXPECT_TRUE(wait_until([&] { return procs.has_line("planner", "planning again"); }, seconds(5)));
  EXPECT_TRUE(procs.exits().empty()) << "ephor-planner exited";
}

// A calibration made for other plane heights than the work cell's is refused
// at start, naming both.
TEST(PlannerProcess, RefusesACalibrationThatDoesNotFitTheWorkcell) {
  const std::string cell = write_temp_file("workcell.pbtxt", "elevation_plane_z_mm: 250\n");
  Processes procs;
  procs.start("planner", bin("ephor-planner"), {"--no-mlock", "--workcell", cell},
              {{"EPHOR_PROCESS", "planner"}, {"EPHOR_HOST", "testhost"}});
  ASSERT_TRUE(wait_until([&] { return !procs.exits().empty(); }, seconds(10)));
  EXPECT_FALSE(procs.exits().front().signaled);
  EXPECT_EQ(procs.exits().front().code, 2);
  EXPECT_TRUE(
      procs.has_line("planner", "elevation plane is at z = 200.0 mm, the work cell's at 250.0"));
}

}  // namespace
}  // namespace ephor::testing
