// The catching page with the real camera and vision: ephor-catch-sim (the
// board, camera and survey), ephor-catch-vision (the board's pose) and
// ephor-catch-display in a private network namespace. The page's JSON and
// camera image are fetched over HTTP as the browser does until the board's
// outline is in the image; the STOP button must reach the bus as ESTOP.

#include <atomic>
#include <csignal>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "common/lcm/bus.h"
#include "common/lcm/channels.h"
#include "ephor/estop_t.hpp"
#include "tests/integration/harness.h"

// Last: httplib.h pulls in <resolv.h>, whose `_res` macro breaks headers included after it.
#include <httplib.h>

namespace ephor::testing {
namespace {

using std::chrono::seconds;

constexpr const char* kUrl = "udpm://239.255.76.67:7668?ttl=0&recv_buf_size=16777216";
constexpr int kPort = 18081;

nlohmann::json get_json(const std::string& path) {
  httplib::Client client("127.0.0.1", kPort);
  client.set_connection_timeout(1);
  client.set_read_timeout(2);
  const auto res = client.Get(path);
  if (!res || res->status != 200) return nullptr;
  return nlohmann::json::parse(res->body, nullptr, false);
}

TEST(CatchDisplay, PageShowsTheBoardInTheImageAndStopsTheArm) {
  std::atomic<int> stops{0}, releases{0};
  Bus bus(kUrl, "catch-display-test");
  bus.subscribe<estop_t>(channels::kEstop,
                         [&](const estop_t& m) { (m.stop ? stops : releases)++; });
  bus.start();

  const std::vector<std::pair<std::string, std::string>> env{{"LCM_DEFAULT_URL", kUrl}};
  Processes p;
  p.start("sim", bin("ephor-catch-sim"),
          {"--seed", "2", "--balls", "0", "--workcell", source_path("deploy/catch/workcell.pbtxt"),
           "--board", source_path("deploy/catch/board.pbtxt"), "--no-mlock"},
          env);
  p.start("vision", bin("ephor-catch-vision"),
          {"--board", source_path("deploy/catch/board.pbtxt"), "--camera",
           source_path("deploy/catch/camera.pbtxt"), "--no-mlock"},
          env);
  p.start("display", bin("ephor-catch-display"),
          {"--http-port", std::to_string(kPort), "--board", source_path("deploy/catch/board.pbtxt"),
           "--camera", source_path("deploy/catch/camera.pbtxt"), "--no-mlock"},
          env);

  nlohmann::json state;
  ASSERT_TRUE(wait_until(
      [&] {
        state = get_json("/api/state");
        return state.is_object() && state["board"].is_object() &&
               state["board"]["outline"].size() == 4 && state["board"]["surveyed"] == true &&
               state["score"].is_object();
      },
      seconds(30)))
      << "the page never showed the board; last state: " << state.dump().substr(0, 2000);

  // The outline lies in the image (each seed's camera keeps the whole board in view).
  const int w = state["frame"]["width"].get<int>(), h = state["frame"]["height"].get<int>();
  ASSERT_GT(w, 0);
  for (const auto& c : state["board"]["outline"]) {
    EXPECT_GE(c[0].get<double>(), -1.0);
    EXPECT_LE(c[0].get<double>(), w);
    EXPECT_GE(c[1].get<double>(), -1.0);
    EXPECT_LE(c[1].get<double>(), h);
  }
  EXPECT_EQ(state["board"]["circles_px"].size(), 4u);

  // The camera image as the page gets it.
  httplib::Client client("127.0.0.1", kPort);
  std::string content_type, jpeg;
  ASSERT_TRUE(wait_until(
      [&] {
        const auto frame = client.Get("/api/frame.jpg");
        if (!frame || frame->status != 200) return false;
        content_type = frame->get_header_value("Content-Type");
        jpeg = frame->body;
        return true;
      },
      seconds(5)));
  EXPECT_EQ(content_type, "image/jpeg");
  EXPECT_GT(jpeg.size(), 1000u);

  // STOP: ESTOP on the bus, repeated while held; the page shows it; release once.
  auto res = client.Post("/api/cmd?cmd=estop&value=true");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 200) << res->body;
  EXPECT_TRUE(wait_until([&] { return stops.load() >= 2; }, seconds(4))) << "STOP not repeated";
  EXPECT_TRUE(get_json("/api/state")["controls"]["estop"].get<bool>());
  res = client.Post("/api/cmd?cmd=estop&value=false");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 200);
  EXPECT_TRUE(wait_until([&] { return releases.load() >= 1; }, seconds(2)));
  EXPECT_FALSE(get_json("/api/state")["controls"]["estop"].get<bool>());
  // A bad request is refused with its reason and sends nothing.
  res = client.Post("/api/cmd?cmd=estop&value=maybe");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 400);
  EXPECT_NE(res->body.find("maybe"), std::string::npos);
  bus.stop();
}

}  // namespace
}  // namespace ephor::testing
