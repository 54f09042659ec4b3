// The sphere page with the real system: deploy/sphere.pbtxt started by the
// launcher (not headless, so its display runs too) in a private network
// namespace, the sphere 5 m out. The page's JSON is fetched over HTTP as the
// browser does until it shows what issue 15 asks for: a raster of range
// returns, an estimate of the sphere, the guidance's filtered sphere with
// its sigma, and the approach history.

#include <cmath>
#include <csignal>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/integration/harness.h"

// Last: httplib.h pulls in <resolv.h>, whose `_res` macro breaks headers included after it.
#include <httplib.h>

namespace ephor::testing {
namespace {

using std::chrono::seconds;

constexpr const char* kUrl = "udpm://239.255.76.67:7670?ttl=0&recv_buf_size=16777216";

// GET path from the page's server as JSON (null when unreachable or not JSON).
nlohmann::json get_json(const std::string& path) {
  httplib::Client client("127.0.0.1", 8082);
  client.set_connection_timeout(1);
  client.set_read_timeout(2);
  const auto res = client.Get(path);
  if (!res || res->status != 200) return nullptr;
  return nlohmann::json::parse(res->body, nullptr, false);
}

TEST(SphereDisplay, PageShowsTheRasterTheEstimateAndItsSigma) {
  Processes p;
  p.start("launch", bin("ephor-launch"),
          {source_path("deploy/sphere.pbtxt"), "--duration", "60", "--start_m", "5", "--seed", "2"},
          {{"LCM_DEFAULT_URL", kUrl}});

  nlohmann::json state;
  ASSERT_TRUE(wait_until(
      [&] {
        state = get_json("/api/state");
        return state.is_object() && state["estimate"].is_object() && state["estimate"]["ok"] &&
               state["guidance"].is_object() && state["guidance"]["tracking"] &&
               state["scan"].is_object() && !state["history"]["guidance"].empty() &&
               !state["sched"].empty() && state["rates_hz"].value("SPHERE_SCAN_LINE", 0.0) > 0.0;
      },
      seconds(40)))
      << "the page never had an estimate; last state: " << state.dump().substr(0, 2000);

  // The estimate is the sphere 5 m out (it started there and closes slowly).
  const double range = state["estimate"]["range_m"].get<double>();
  EXPECT_GT(range, 1.0);
  EXPECT_LT(range, 5.5);
  // The guidance's sigma is there and small (mm to cm at 5 m).
  for (int i = 0; i < 3; ++i) {
    const double s = state["guidance"]["sigma_m"][i].get<double>();
    EXPECT_GT(s, 0.0) << "axis " << i;
    EXPECT_LT(s, 0.1) << "axis " << i;
  }
  EXPECT_EQ(state["truth"]["phase"], "approach");
  // The task table and the rates came with it (the wait above asked for them).
  EXPECT_GT(state["sched"].size(), 0u);

  // The raster: returns of the sphere, in range bins, about where the estimate is.
  const auto scan = get_json("/api/scan");
  ASSERT_TRUE(scan.is_object());
  ASSERT_GT(scan["points"].size(), 10u);
  int in_bins = 0;
  for (const auto& pt : scan["points"]) {
    const int bin = pt[3].get<int>();
    EXPECT_GE(bin, -1);
    EXPECT_LT(bin, 8);
    if (bin >= 0 && std::abs(pt[2].get<double>() - range) < 0.5) ++in_bins;
  }
  EXPECT_GT(in_bins, 10) << "no returns near the estimated range";

  // The page itself is served.
  httplib::Client client("127.0.0.1", 8082);
  const auto page = client.Get("/");
  ASSERT_TRUE(page);
  EXPECT_NE(page->body.find("sphere.js"), std::string::npos);
  EXPECT_EQ(client.Get("/sphere.js")->status, 200);
  EXPECT_EQ(client.Get("/ephor_page.js")->status, 200);
  // No commands on this page: refused with a reason.
  const auto cmd = client.Post("/api/cmd?cmd=estop&value=true");
  ASSERT_TRUE(cmd);
  EXPECT_EQ(cmd->status, 400);
  p.signal("launch", SIGINT);
}

}  // namespace
}  // namespace ephor::testing
