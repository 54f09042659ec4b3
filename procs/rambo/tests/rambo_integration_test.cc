// The whole RAMBO slice (deploy/rambo.pbtxt) started headless by the launcher,
// as a user runs it, in a private network namespace: the simulator's slowly
// tumbling target (2 deg/s), pose from its oracle image triples (the
// manifest's default: projected vertices + noise, not the features process's), the
// rigid-body predictor, the planner and the shared comm and arm. A listener
// on the same bus checks that the laser tags at least one diode within 80 s,
// that poses are mostly found and close to the truth, and that bad input
// (a NaN prediction, a features message with NaN pixels, bytes that are no
// message) is refused by name while the loop goes on. The run is stopped by
// SIGINT; the simulator's summary must then name the tagged diode.

#include <csignal>
#include <fstream>
#include <mutex>
#include <sstream>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "common/lcm/bus.h"
#include "common/rambo/rambo_channels.h"
#include "ephor/rambo_features_t.hpp"
#include "ephor/rambo_indicator_t.hpp"
#include "ephor/rambo_pose_t.hpp"
#include "ephor/rambo_prediction_t.hpp"
#include "tests/integration/harness.h"

namespace ephor::testing {
namespace {

using std::chrono::seconds;

constexpr const char* kUrl = "udpm://239.255.76.67:7672?ttl=0&recv_buf_size=16777216";

struct Heard {
  std::mutex mutex;
  int max_tagged = 0;
  int poses = 0, found = 0, predictions = 0;
};

TEST(Rambo, HeadlessRunTagsADiodeOfASlowlyTumblingTarget) {
  Heard heard;
  Bus bus(kUrl, "rambo-test");
  bus.subscribe<rambo_indicator_t>(rambo::channels::kIndicator, [&](const rambo_indicator_t& m) {
    std::lock_guard<std::mutex> lock(heard.mutex);
    heard.max_tagged = std::max(heard.max_tagged, static_cast<int>(m.tagged_count));
  });
  bus.subscribe<rambo_pose_t>(rambo::channels::kPose, [&](const rambo_pose_t& m) {
    std::lock_guard<std::mutex> lock(heard.mutex);
    ++heard.poses;
    heard.found += m.found ? 1 : 0;
  });
  bus.subscribe<rambo_prediction_t>(rambo::channels::kPrediction, [&](const rambo_prediction_t& m) {
    if (m.header.sender == "rambo-test") return;
    std::lock_guard<std::mutex> lock(heard.mutex);
    heard.predictions += m.fitted ? 1 : 0;
  });
  bus.start();

  const std::string summary = write_temp_file("rambo_summary.json", "");
  Processes p;
  p.start("launch", bin("ephor-launch"),
          {source_path("deploy/rambo.pbtxt"), "--headless", "--seed", "1", "--max_s", "85",
           "--summary", summary},
          {{"LCM_DEFAULT_URL", kUrl}});
  ASSERT_TRUE(wait_until(
      [&] {
        std::lock_guard<std::mutex> lock(heard.mutex);
        return heard.predictions >= 3;
      },
      seconds(30)))
      << "no predictions";
  {
    rambo_prediction_t bad{};
    bad.fitted = true;
    bad.position_mm[0] = std::nan("");
    bad.orientation_wxyz[0] = 1.0;
    bad.principal_moments[0] = bad.principal_moments[1] = bad.principal_moments[2] = 1.0;
    bus.publish(rambo::channels::kPrediction, bad);
    rambo_features_t f{};
    f.frame_index = 999999;
    f.source = "rambo-test";
    f.num_triples = 1;
    f.triples_px = {{std::nan(""), 1.0, 2.0, 3.0, 4.0, 5.0}};
    bus.publish(rambo::channels::kFeaturesOracle, f);
    const char garbage[] = "not an lcm message";
    bus.publish_raw(rambo::channels::kPose, garbage, sizeof garbage);
  }
  const bool tagged = wait_until(
      [&] {
        std::lock_guard<std::mutex> lock(heard.mutex);
        return heard.max_tagged >= 1;
      },
      seconds(80));
  p.signal("launch", SIGINT);
  ASSERT_TRUE(wait_until(
      [&] {
        for (const auto& e : p.exits())
          if (e.name == "launch") return true;
        return false;
      },
      seconds(20)))
      << "the run did not stop";
  bus.stop();
  EXPECT_TRUE(tagged) << "no diode tagged in 80 s";
  EXPECT_TRUE(p.has_line("launch", "RAMBO_PREDICTION from rambo-test ignored: not finite"));
  EXPECT_TRUE(p.has_line("launch", "RAMBO_FEATURES frame 999999 from rambo-test refused"));
  {
    std::lock_guard<std::mutex> lock(heard.mutex);
    std::fprintf(stderr, "%d poses (%d found), %d predictions, %d tagged\n", heard.poses,
                 heard.found, heard.predictions, heard.max_tagged);
    EXPECT_GT(heard.found, heard.poses / 3) << "pose rarely found";
  }
  std::ifstream in(summary);
  nlohmann::json s;
  ASSERT_NO_THROW(in >> s) << "no JSON summary at " << summary;
  std::fprintf(stderr, "summary: %s\n", s.dump().c_str());
  EXPECT_GE(s.at("tagged").get<int>(), 1);
  EXPECT_EQ(s.at("diodes").get<int>(), 4);
  EXPECT_EQ(s.at("pose_features_source").get<std::string>(), "oracle");
  ASSERT_FALSE(s.at("pose_error_mm").is_null());
  EXPECT_LT(s.at("pose_error_mm").at("p50").get<double>(), 5.0);
  EXPECT_LT(s.at("pose_error_deg").at("p50").get<double>(), 1.0);
  // The summary fields, present and sane.
  ASSERT_TRUE(s.contains("time_to_all_s"));
  EXPECT_TRUE(s.at("time_to_all_s").is_null() || s.at("time_to_all_s").get<double>() > 0.0);
  ASSERT_EQ(s.at("tasks").size(), s.at("tagged").get<std::size_t>());
  double previous_s = 0.0;
  for (std::size_t k = 0; k < s.at("tasks").size(); ++k) {
    const auto& t = s.at("tasks")[k];
    EXPECT_EQ(t.at("order").get<std::size_t>(), k + 1);
    EXPECT_GE(t.at("diode").get<int>(), 0);
    EXPECT_LT(t.at("diode").get<int>(), 4);
    EXPECT_FALSE(t.at("name").get<std::string>().empty());
    EXPECT_NEAR(t.at("time_s").get<double>(), t.at("tagged_s").get<double>() - previous_s, 1e-9);
    EXPECT_GE(t.at("time_s").get<double>(), 1.0) << "a diode is lit 1 s before it is tagged";
    previous_s = t.at("tagged_s").get<double>();
  }
  for (const char* key : {"pose_error_mm", "pose_error_deg", "pose_ms"}) {
    const auto& v = s.at(key);
    ASSERT_FALSE(v.is_null()) << key;
    EXPECT_GE(v.at("p50").get<double>(), 0.0) << key;
    EXPECT_GE(v.at("p99").get<double>(), v.at("p50").get<double>()) << key;
  }
  EXPECT_LT(s.at("pose_ms").at("p50").get<double>(), 150.0) << "pose within its deadline";
  for (const char* h : {"0.5s", "1.0s", "2.0s"}) {
    const auto& v = s.at("prediction_error_mm").at(h);
    ASSERT_FALSE(v.is_null()) << h;
    EXPECT_LT(v.at("p50").get<double>(), 50.0) << h;
  }
  const auto& counts = s.at("reaching_trajectories_computed");
  ASSERT_FALSE(counts.is_null());
  for (const char* m : {"greedy", "exhaustive", "dynamic_programming"})
    EXPECT_GE(counts.at(m).get<int>(), 1) << m;
  EXPECT_GE(counts.at("exhaustive").get<int>(), counts.at("greedy").get<int>());
  ASSERT_TRUE(s.at("deadline_misses").is_number_integer()) << "no scheduler status heard";
  EXPECT_GE(s.at("deadline_misses").get<int64_t>(), 0);
  ASSERT_TRUE(s.at("rt").is_boolean());
  EXPECT_EQ(s.at("sched_hosts").get<int>(), 4) << "world, vision, planning, robot";
}

// A bad model file or diode count: every process that reads the model says
// what is wrong in one line and exits with status 2, before touching the bus.
TEST(Rambo, BadModelFilesAreRefusedInOneLineWithStatusTwo) {
  std::ifstream in(source_path("deploy/rambo/target.pbtxt"));
  std::stringstream text;
  text << in.rdbuf();
  auto with = [&](const std::string& from, const std::string& to) {
    std::string t = text.str();
    const auto at = t.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return t.replace(at, from.size(), to);
  };
  const std::string missing = write_temp_file(
      "missing_vertex.pbtxt", with("face { vertex: [7, 8, 9] }", "face { vertex: [7, 8, 12] }"));
  const std::string off = write_temp_file(
      "goal_off.pbtxt", with("lens_mm { x: -30 y: -90 z: 0 }", "lens_mm { x: -30 y: -130 z: 0 }"));
  const std::string nan = write_temp_file(
      "nan.pbtxt", with("vertex { x: 120 y: 90 z: 70 }", "vertex { x: nan y: 90 z: 70 }"));
  // The first four diodes only.
  std::string first_four = text.str();
  first_four = first_four.substr(0, first_four.find("# On the cut face's centroid"));
  const std::string four = write_temp_file("four_diodes.pbtxt", first_four);
  struct Case {
    std::string exe, model, expected;
    std::vector<std::string> extra;
  };
  const std::vector<Case> cases{
      {"ephor-rambo-sim", missing, "face[6]: face 6 index 2 names vertex 12, which is missing", {}},
      {"ephor-rambo-pose", missing, "face 6 index 2 names vertex 12", {}},
      {"ephor-rambo-predictor",
       off,
       "diode[2].lens_mm: goal point diode[2] ('right') is off the target: its lens is 40 mm "
       "outside the surface",
       {}},
      {"ephor-rambo-planner", nan, "vertex[4]: is not finite (nan, 90, 70)", {}},
      {"ephor-rambo-planner",
       four,
       "--diodes 6: " + four + " carries 4 diodes (1-4)",
       {"--diodes", "6"}},
  };
  for (const Case& k : cases) {
    Processes p;
    std::vector<std::string> args{"--no-mlock", "--model", k.model, "--duration", "5"};
    args.insert(args.end(), k.extra.begin(), k.extra.end());
    p.start("proc", bin(k.exe), args, {{"LCM_DEFAULT_URL", kUrl}});
    ASSERT_TRUE(wait_until([&] { return !p.exits().empty(); }, seconds(10))) << k.exe;
    const auto e = p.exits().front();
    EXPECT_EQ(e.code, 2) << k.exe << " " << e.describe();
    EXPECT_TRUE(p.has_line("proc", k.expected)) << k.exe << ": expected '" << k.expected << "'";
    EXPECT_EQ(p.lines("proc").size(), 1u) << k.exe << ": one line";
  }
}

}  // namespace
}  // namespace ephor::testing
