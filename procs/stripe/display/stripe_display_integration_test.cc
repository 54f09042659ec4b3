// The light-stripe page with the real system (deploy/stripe.pbtxt with its
// display, as `tools/ephor demo stripe` runs it) in a private network
// namespace: the page's state API serves the cloud as it grows - /api/state's
// point count rises stripe by stripe during the scan and /api/cloud carries
// that many points (x, y, z in mm, table frame) - and the camera's image.

#include <algorithm>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/integration/harness.h"
// Last: httplib.h pulls in <resolv.h>, whose `_res` macro breaks headers included after it.
#include <httplib.h>

namespace ephor::testing {
namespace {

using std::chrono::milliseconds;
using std::chrono::seconds;

constexpr const char* kUrl = "udpm://239.255.76.67:7677?ttl=0&recv_buf_size=16777216";

httplib::Result get(const std::string& path) {
  httplib::Client client("127.0.0.1", 8084);
  client.set_connection_timeout(1);
  client.set_read_timeout(2);
  return client.Get(path);
}

nlohmann::json get_json(const std::string& path) {
  const auto res = get(path);
  if (!res || res->status != 200) return nullptr;
  return nlohmann::json::parse(res->body, nullptr, false);
}

TEST(StripeDisplay, StateApiServesTheGrowingCloud) {
  Processes p;
  p.start("launch", bin("ephor-launch"),
          {source_path("deploy/stripe.pbtxt"), "--duration", "40", "--scene",
           source_path("deploy/stripe/scenes/pyramid.obj"), "--region=-40,-30,40,30"},
          {{"LCM_DEFAULT_URL", kUrl}});
  // The point count seen at each poll while the scan runs.
  std::vector<int64_t> counts;
  bool complete = false;
  ASSERT_TRUE(wait_until(
      [&] {
        const nlohmann::json s = get_json("/api/state");
        if (s.is_null() || !s.contains("cloud")) return false;
        const int64_t n = s["cloud"]["points"].get<int64_t>();
        if (counts.empty() || n != counts.back()) counts.push_back(n);
        complete = s["cloud"]["complete"].get<bool>();
        return complete;
      },
      seconds(35)))
      << "the scan's cloud was not completed on the page";
  std::string seen;
  for (int64_t n : counts) seen += " " + std::to_string(n);
  std::fprintf(stderr, "points on the page as the scan ran:%s\n", seen.c_str());
  // Growing: several counts, each larger than the one before.
  const size_t nonzero = static_cast<size_t>(
      std::count_if(counts.begin(), counts.end(), [](int64_t n) { return n > 0; }));
  EXPECT_GE(nonzero, 3u) << seen;
  EXPECT_TRUE(std::is_sorted(counts.begin(), counts.end())) << seen;
  const nlohmann::json cloud = get_json("/api/cloud");
  ASSERT_FALSE(cloud.is_null());
  EXPECT_EQ(cloud["points"].get<int64_t>(), counts.back());
  EXPECT_EQ(cloud["xyz"].size(), 3 * static_cast<size_t>(counts.back()));
  // The page and its three.js, and the camera's newest image.
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
