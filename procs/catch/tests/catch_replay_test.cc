// Replay of a recorded catch (issue 14, the design card's replay-based
// testing), in a private network namespace, with the tools a user has:
//  1. a headless run of deploy/catch.pbtxt (one ball, seed 2) recorded by the
//     launcher's `--record` (lcm-logger);
//  2. a fresh ephor-catch-worldmodel is started and `lcm-logplayer` plays the
//     log's world-model inputs to it (CATCH_BOARD_POSE, CATCH_SURVEY,
//     CATCH_PEGS, CATCH_BALL); its outputs are heard.
// The world model takes the newest CATCH_BALL (a busy machine makes it skip
// one now and then, and a skipped measurement changes the filter's later
// states), so the replay is given only the balls the live model answered,
// and the replaying model takes every one of them (--every-ball).
// Every CATCH_WORLD of the live run must come back byte-identical from the
// replay (matched by the frame's capture time), except the fields that say
// when it was made, not what: header.utime, header.seq and latency_ms.

#include <unistd.h>

#include <filesystem>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>

#include "common/catch/catch_channels.h"
#include "common/lcm/bus.h"
#include "ephor/catch_ball_t.hpp"
#include "ephor/catch_world_t.hpp"
#include "tests/integration/harness.h"

namespace ephor::testing {
namespace {

namespace fs = std::filesystem;
using std::chrono::seconds;

// The manifest's port (deploy/catch.pbtxt), private to this namespace.
constexpr const char* kUrl = "udpm://239.255.76.67:7668?ttl=0&recv_buf_size=16777216";

std::vector<uint8_t> what_not_when(catch_world_t m) {
  m.header.utime = 0;
  m.header.seq = 0;
  m.latency_ms = 0.0F;
  std::vector<uint8_t> bytes(static_cast<size_t>(m.getEncodedSize()));
  m.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  return bytes;
}

TEST(CatchReplay, RecordedBallsReplayToByteIdenticalWorldModelOutput) {
  const fs::path dir =
      fs::temp_directory_path() / ("ephor-catch-replay-" + std::to_string(getpid()));
  fs::create_directories(dir);
  const std::string log_path = (dir / "run.lcm").string();

  // 1. The live run, recorded. What is tested is the replay, so a live run
  // that never tracked its ball (seed 2's ball is now and then first seen
  // only once it is past the top of the board, which the world model does
  // not take as a ball's start: issue 14's open tracking misses) is made
  // again, up to three runs, each said.
  std::map<int64_t, catch_world_t> live;
  int balls = 0;
  for (int run = 1; run <= 3; ++run) {
    {
      Processes p;
      p.start("launch", bin("ephor-launch"),
              {source_path("deploy/catch.pbtxt"), "--headless", "--duration", "40", "--balls", "1",
               "--seed", "2", "--record", log_path});
      ASSERT_TRUE(wait_until([&] { return p.exited("launch"); }, seconds(60)));
      ASSERT_EQ(p.exits().front().code, 0) << "the launcher reported a failed process";
    }
    live.clear();
    balls = 0;
    lcm::LogFile log(log_path, "r");
    ASSERT_TRUE(log.good()) << log_path;
    while (const lcm::LogEvent* e = log.readNextEvent()) {
      if (e->channel == catching::channels::kBall) ++balls;
      if (e->channel != catching::channels::kWorld) continue;
      catch_world_t m;
      if (m.decode(e->data, 0, static_cast<int>(e->datalen)) == static_cast<int>(e->datalen))
        live[m.utime] = m;
    }
    int tracking = 0;
    for (const auto& [utime, m] : live) tracking += m.status == catch_world_t::STATUS_TRACKING;
    if (tracking >= 10) break;
    std::fprintf(stderr, "live run %d tracked its ball in %d frames: running it again\n", run,
                 tracking);
    ASSERT_LT(run, 3) << "three live runs never tracked the ball";
  }
  ASSERT_GE(balls, 60) << "CATCH_BALL messages in the log (one per frame)";

  // The world model's inputs, without the balls the live model skipped.
  const std::string inputs_path = (dir / "inputs.lcm").string();
  int skipped = 0;
  {
    lcm::LogFile in(log_path, "r");
    lcm::LogFile out(inputs_path, "w");
    ASSERT_TRUE(in.good() && out.good());
    while (const lcm::LogEvent* e = in.readNextEvent()) {
      const bool ball = e->channel == catching::channels::kBall;
      if (!ball && e->channel != catching::channels::kBoardPose &&
          e->channel != catching::channels::kSurvey && e->channel != catching::channels::kPegs)
        continue;
      if (ball) {
        catch_ball_t b;
        if (b.decode(e->data, 0, static_cast<int>(e->datalen)) != static_cast<int>(e->datalen))
          continue;
        if (live.count(b.utime) == 0) {
          ++skipped;
          continue;
        }
      }
      lcm::LogEvent copy = *e;
      out.writeEvent(&copy);
    }
  }
  std::fprintf(stderr, "%d balls, %zu answered live, %d skipped live (not replayed)\n", balls,
               live.size(), skipped);

  // 2. The log's world-model inputs through a fresh world model.
  std::map<int64_t, catch_world_t> replayed;
  {
    const std::vector<std::pair<std::string, std::string>> env{{"LCM_DEFAULT_URL", kUrl}};
    std::mutex mutex;
    Bus bus(kUrl, "replay-test");
    bus.subscribe<catch_world_t>(catching::channels::kWorld, [&](const catch_world_t& m) {
      std::lock_guard<std::mutex> lock(mutex);
      replayed[m.utime] = m;
    });
    bus.start();
    Processes p;
    // The world model's arguments as deploy/catch.pbtxt gives them, and
    // --every-ball.
    p.start("worldmodel", bin("ephor-catch-worldmodel"),
            {"--no-mlock", "--name", "worldmodel", "--board", "deploy/catch/board.pbtxt",
             "--camera", "deploy/catch/camera.pbtxt", "--spread-samples=32", "--every-ball"},
            env);
    ASSERT_TRUE(wait_until([&] { return p.has_line("worldmodel", "ready:"); }, seconds(10)));
    p.start("player", "/usr/bin/lcm-logplayer", {"--lcm-url", kUrl, inputs_path}, env);
    EXPECT_TRUE(wait_until([&] { return p.exited("player"); }, seconds(120)));
    const auto all_back = [&] {
      std::lock_guard<std::mutex> lock(mutex);
      return replayed.size() >= live.size();
    };
    EXPECT_TRUE(wait_until(all_back, seconds(5)))
        << "the replay gave " << replayed.size() << " of " << live.size() << " outputs back";
    bus.stop();
  }

  int compared = 0, differing = 0, missing = 0;
  for (const auto& [utime, m] : live) {
    const auto it = replayed.find(utime);
    if (it == replayed.end()) {
      if (++missing <= 5) ADD_FAILURE() << "frame " << m.frame_index << " not replayed";
      continue;
    }
    ++compared;
    if (what_not_when(m) != what_not_when(it->second)) {
      if (++differing <= 5) {
        ADD_FAILURE() << "frame " << m.frame_index << ": live status " << int{m.status} << " ("
                      << m.position_b_mm[0] << ", " << m.position_b_mm[1] << ") vs replay status "
                      << int{it->second.status} << " (" << it->second.position_b_mm[0] << ", "
                      << it->second.position_b_mm[1] << ")";
      }
    }
  }
  EXPECT_EQ(compared, static_cast<int>(live.size())) << "live outputs missing from the replay";
  EXPECT_EQ(differing, 0);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace ephor::testing
