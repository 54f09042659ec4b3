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
}

}  // namespace
}  // namespace ephor::testing
