// The RAMBO page with the real system (deploy/rambo.pbtxt with its display,
// as `tools/ephor demo rambo` runs it) in a private network namespace: the
// page's state API, polled as the browser polls it, carries the camera
// image's features (corners and edges) and the triangles the pose matched,
// the target's estimated pose near its true one, the planned order of the
// diodes, and the diodes as the target's indicator electronics last said
// (tagged, lit, the beam's angle to each: compared with the indicator's
// messages heard on the bus, so the test need not wait the 20-120 s a tag
// takes); the page loads three.js and the camera's image and model are served.

#include <cmath>
#include <mutex>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "common/lcm/bus.h"
#include "common/rambo/rambo_channels.h"
#include "common/time/clock.h"
#include "ephor/rambo_indicator_t.hpp"
#include "tests/integration/harness.h"
// Last: httplib.h pulls in <resolv.h>, whose `_res` macro breaks headers included after it.
#include <httplib.h>

namespace ephor::testing {
namespace {

using std::chrono::seconds;

constexpr const char* kUrl = "udpm://239.255.76.67:7672?ttl=0&recv_buf_size=16777216";

httplib::Result get(const std::string& path) {
  httplib::Client client("127.0.0.1", 8083);
  client.set_connection_timeout(1);
  client.set_read_timeout(2);
  return client.Get(path);
}

nlohmann::json get_json(const std::string& path) {
  const auto res = get(path);
  if (!res || res->status != 200) return nullptr;
  return nlohmann::json::parse(res->body, nullptr, false);
}

TEST(RamboDisplay, StateApiCarriesImagePosesOrderAndTaggedDiodes) {
  // The indicator's messages, to compare the page's diodes with.
  std::mutex mutex;
  std::vector<rambo_indicator_t> heard;
  Bus bus(kUrl, "rambo-display-test");
  bus.subscribe<rambo_indicator_t>(rambo::channels::kIndicator, [&](const rambo_indicator_t& m) {
    std::lock_guard<std::mutex> lock(mutex);
    heard.push_back(m);
    if (heard.size() > 40) heard.erase(heard.begin());
  });
  bus.start();
  Processes p;
  p.start("launch", bin("ephor-launch"),
          {source_path("deploy/rambo.pbtxt"), "--seed", "2", "--max_s", "80"},
          {{"LCM_DEFAULT_URL", kUrl}});
  // What the polls have seen so far.
  bool features = false, triangles = false, poses = false, order = false;
  double error_mm = -1.0;
  const int64_t t0 = mono_ns();
  ASSERT_TRUE(wait_until(
      [&] {
        const nlohmann::json s = get_json("/api/state");
        if (s.is_null() || !s.contains("image")) return false;
        const auto& f = s["image"]["features"];
        features = features || (!f.is_null() && f["corners"].size() >= 4 && !f["edges"].empty());
        triangles = triangles || !s["image"]["matched_triangles"].empty();
        const auto& est = s["pose"]["estimated"];
        if (!est.is_null() && !s["pose"]["true"].is_null() && !est["error_mm"].is_null()) {
          poses = true;
          error_mm = est["error_mm"].get<double>();
        }
        order = order || (!s["plan"].is_null() && !s["plan"]["order"].empty());
        return features && triangles && poses && order;
      },
      seconds(60)))
      << "seen on the page: features " << features << ", matched triangles " << triangles
      << ", estimated and true poses " << poses << ", an order " << order;
  std::fprintf(stderr, "page: all seen after %.1f s; newest pose error %.2f mm\n",
               static_cast<double>(mono_ns() - t0) * 1e-9, error_mm);
  // The diodes as the target's electronics last said: the page's tagged
  // flags, lit diode and beam angles are one of the indicator's messages.
  std::string diodes_seen;
  ASSERT_TRUE(wait_until(
      [&] {
        const nlohmann::json s = get_json("/api/state");
        if (s.is_null() || !s.contains("diodes")) return false;
        diodes_seen = s["diodes"].dump();
        std::lock_guard<std::mutex> lock(mutex);
        for (const rambo_indicator_t& m : heard) {
          if (static_cast<int>(s["diodes"].size()) != m.num_diodes) continue;
          bool same = s["indicator"]["tagged"].get<int>() == m.tagged_count;
          for (int i = 0; i < m.num_diodes && same; ++i) {
            const auto& d = s["diodes"][static_cast<std::size_t>(i)];
            same = d["tagged"].get<bool>() == m.tagged[static_cast<std::size_t>(i)] &&
                   d["lit"].get<bool>() == (m.lit_diode == i) &&
                   std::abs(d["beam_angle_deg"].get<double>() -
                            m.beam_angle_deg[static_cast<std::size_t>(i)]) <= 0.051;
          }
          if (same) return true;
        }
        return false;
      },
      seconds(10)))
      << "the page's diodes are none of the indicator's last messages: " << diodes_seen;
  EXPECT_LT(error_mm, 50.0);
  const nlohmann::json s = get_json("/api/state");
  ASSERT_FALSE(s.is_null());
  EXPECT_EQ(s["diodes"].size(), 4u);
  EXPECT_FALSE(s["laser"].is_null());
  // The 3-D view's model, the page with three.js, and the camera's image.
  const nlohmann::json model = get_json("/api/model");
  ASSERT_FALSE(model.is_null());
  EXPECT_EQ(model["vertices"].size(), 10u);
  EXPECT_EQ(model["diodes"].size(), 4u);
  const auto page = get("/");
  ASSERT_TRUE(page);
  EXPECT_NE(page->body.find("/lib/three.min.js"), std::string::npos);
  const auto three = get("/lib/three.min.js");
  ASSERT_TRUE(three);
  EXPECT_EQ(three->status, 200);
  const auto jpeg = get("/api/frame.jpg");
  ASSERT_TRUE(jpeg);
  EXPECT_EQ(jpeg->status, 200);
  p.stop_all();
}

}  // namespace
}  // namespace ephor::testing
