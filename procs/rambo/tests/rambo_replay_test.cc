// Replay of a recorded RAMBO run (issue 17: "a recorded log replays to
// byte-identical pose output"), in a private network namespace, with the
// tools a user has:
//  1. a headless run of deploy/rambo.pbtxt (seed 2, 20 s) recorded by the
//     launcher's `--record` (lcm-logger);
//  2. a fresh ephor-rambo-pose is started and `lcm-logplayer` plays the log's
//     pose inputs to it (RAMBO_FEATURES, the image triples the features
//     process found in the frames, the manifest's default; ARM_STATE, the camera's pose;
//     RAMBO_PREDICTION, section 5's prior); its RAMBO_POSE messages are heard.
// Every RAMBO_POSE of the live run must come back byte-identical from the
// replay (matched by the frame's capture time), except the fields that say
// when and how long, not what: header.utime, header.seq and pose_ms (CPU
// time). A third pass replays the same log without the prior (section 5's
// pruning off) and must differ: the comparison can fail.

#include <unistd.h>

#include <filesystem>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>

#include "common/lcm/bus.h"
#include "common/rambo/rambo_channels.h"
#include "ephor/rambo_pose_t.hpp"
#include "tests/integration/harness.h"

namespace ephor::testing {
namespace {

namespace fs = std::filesystem;
using std::chrono::seconds;

// The manifest's port (deploy/rambo.pbtxt), private to this namespace.
constexpr const char* kUrl = "udpm://239.255.76.67:7672?ttl=0&recv_buf_size=16777216";

std::vector<uint8_t> what_not_when(rambo_pose_t m) {
  m.header.utime = 0;
  m.header.seq = 0;
  m.pose_ms = 0.0;
  std::vector<uint8_t> bytes(static_cast<size_t>(m.getEncodedSize()));
  m.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  return bytes;
}

// The log's pose inputs through a fresh pose process with `extra` flags; its
// poses by capture utime.
// `expect` poses are waited for (5 s after the player ends); with `strict`,
// fewer is a failure.
std::map<int64_t, rambo_pose_t> replay(const std::string& log_path,
                                       const std::vector<std::string>& extra, std::size_t expect,
                                       bool strict) {
  std::map<int64_t, rambo_pose_t> replayed;
  const std::vector<std::pair<std::string, std::string>> env{{"LCM_DEFAULT_URL", kUrl}};
  std::mutex mutex;
  Bus bus(kUrl, "replay-test");
  bus.subscribe<rambo_pose_t>(rambo::channels::kPose, [&](const rambo_pose_t& m) {
    std::lock_guard<std::mutex> lock(mutex);
    replayed[m.utime] = m;
  });
  bus.start();
  Processes p;
  std::vector<std::string> args{"--no-mlock", "--name", "pose", "--model",
                                "deploy/rambo/target.pbtxt", "--features-channel",
                                rambo::channels::kFeatures,
                                // Never drop a frame, however slow this
                                // process is on a loaded machine (the live
                                // run dropped none: checked below).
                                "--max-behind", "100000"};
  args.insert(args.end(), extra.begin(), extra.end());
  p.start("pose", bin("ephor-rambo-pose"), args, env);
  EXPECT_TRUE(wait_until([&] { return p.has_line("pose", "ready:"); }, seconds(10)));
  p.start("player", "/usr/bin/lcm-logplayer",
          {"--lcm-url", kUrl, "--speed", "0.5", "--regexp",
           "^(RAMBO_FEATURES|ARM_STATE|RAMBO_PREDICTION)$", log_path},
          env);
  EXPECT_TRUE(wait_until([&] { return p.exited("player"); }, seconds(90)));
  const bool all_back = wait_until(
      [&] {
        std::lock_guard<std::mutex> lock(mutex);
        return replayed.size() + 1 >= expect;
      },
      seconds(strict ? 30 : 5));
  if (strict) {
    std::lock_guard<std::mutex> lock(mutex);
    // One datagram lost between lcm-logplayer and the pose process was seen
    // once on a loaded machine (CI, 2026-11-28: 75 of 76): the log is played
    // at half speed, and one lost input is allowed; every pose that came back
    // must still be identical.
    EXPECT_TRUE(all_back) << "the replay gave " << replayed.size() << " of " << expect
                          << " poses back";
  }
  bus.stop();
  std::lock_guard<std::mutex> lock(mutex);
  return replayed;
}

// Poses of `live` that `replayed` gives back byte-identical (what, not when);
// `differing` gets the others, `missing` those not given back.
int identical(const std::map<int64_t, rambo_pose_t>& live,
              const std::map<int64_t, rambo_pose_t>& replayed, int* differing, int* missing,
              bool report) {
  int same = 0;
  *differing = *missing = 0;
  for (const auto& [utime, m] : live) {
    const auto it = replayed.find(utime);
    if (it == replayed.end()) {
      ++*missing;
      continue;
    }
    if (what_not_when(m) == what_not_when(it->second)) {
      ++same;
    } else if (++*differing <= 5 && report) {
      ADD_FAILURE() << "frame " << m.frame_index << ": live found " << m.found << " ("
                    << m.target_t_mm[0] << ", " << m.target_t_mm[1] << ", " << m.target_t_mm[2]
                    << ") mm, " << m.matches_tried << " matches, '" << m.reason
                    << "' vs replay found " << it->second.found << " (" << it->second.target_t_mm[0]
                    << ", " << it->second.target_t_mm[1] << ", " << it->second.target_t_mm[2]
                    << ") mm, " << it->second.matches_tried << " matches, '" << it->second.reason
                    << "'";
    }
  }
  return same;
}

TEST(RamboReplay, RecordedPoseInputsReplayToByteIdenticalPoses) {
  const fs::path dir =
      fs::temp_directory_path() / ("ephor-rambo-replay-" + std::to_string(getpid()));
  fs::create_directories(dir);
  const std::string log_path = (dir / "run.lcm").string();
  bool live_pose_dropped_none = false;

  // 1. The live run, recorded; the simulator ends it after max_s.
  {
    Processes p;
    p.start("launch", bin("ephor-launch"),
            {source_path("deploy/rambo.pbtxt"), "--headless", "--seed", "2", "--max_s", "20",
             "--record", log_path});
    ASSERT_TRUE(wait_until([&] { return p.exited("launch"); }, seconds(60)));
    ASSERT_EQ(p.exits().front().code, 0) << "the launcher reported a failed process";
    live_pose_dropped_none = p.has_line("launch", " bad messages, 0 frames dropped behind");
  }
  std::map<int64_t, rambo_pose_t> live;
  int features = 0;
  {
    lcm::LogFile log(log_path, "r");
    ASSERT_TRUE(log.good()) << log_path;
    while (const lcm::LogEvent* e = log.readNextEvent()) {
      if (e->channel == rambo::channels::kFeatures) ++features;
      if (e->channel != rambo::channels::kPose) continue;
      rambo_pose_t m;
      if (m.decode(e->data, 0, static_cast<int>(e->datalen)) == static_cast<int>(e->datalen))
        live[m.utime] = m;
    }
  }
  // 100 at 5 Hz for 20 s; fewer when the machine is loaded (seen: 29 at a
  // load average of 16 on 2 cores), which the comparison does not need.
  ASSERT_GE(features, 20) << "RAMBO_FEATURES messages in the log (5 Hz for 20 s)";
  int found = 0, pruned = 0;
  for (const auto& [utime, m] : live) {
    found += m.found ? 1 : 0;
    pruned += m.pruned ? 1 : 0;
  }
  ASSERT_GE(found, 10) << "the live run rarely found the pose";
  ASSERT_TRUE(live_pose_dropped_none) << "the live pose process dropped frames (--max-behind)";
  ASSERT_GE(pruned, 8) << "the live run rarely pruned by a prior";

  // 2. The same inputs through a fresh pose process: byte-identical.
  const auto same_flags = replay(log_path, {}, live.size(), true);
  int differing = 0, missing = 0;
  const int same = identical(live, same_flags, &differing, &missing, true);
  std::fprintf(stderr,
               "live %zu poses (%d found, %d pruned): replay %d identical, %d differ, %d missing\n",
               live.size(), found, pruned, same, differing, missing);
  EXPECT_LE(missing, 1) << "live poses missing from the replay (one lost datagram is allowed)";
  EXPECT_EQ(differing, 0);
  EXPECT_EQ(same + missing, static_cast<int>(live.size()));

  // 3. Without the prior, the same log gives other poses (other matches
  // tried, other clusters): the comparison above is able to fail.
  const auto no_prior = replay(log_path, {"--prior-max-age-s", "0"}, live.size(), false);
  const int same_without = identical(live, no_prior, &differing, &missing, false);
  std::fprintf(stderr, "without the prior: %d identical, %d differ, %d missing\n", same_without,
               differing, missing);
  EXPECT_GE(differing, pruned / 2) << "pruning made no difference: the comparison cannot fail";
  fs::remove_all(dir);
}

}  // namespace
}  // namespace ephor::testing
