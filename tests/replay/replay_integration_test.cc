// Deterministic replay (tools/ephor replay, ephor-replay) of a recorded
// shepherding run, in a private network namespace:
//  (a) the run (ephor-sim + ephor-vision + ephor-worldmodel, recorded here
//      with lcm::LogFile) replayed through fresh vision and world-model
//      processes gives exactly the recorded object tracks, and two replays
//      give byte-identical output logs;
//  (b) the replayed tracks, scored against the logged GROUND_TRUTH, keep
//      every sheep's id and are within 1 px of the true mark centre while
//      visible;
//  (c) a log with a dropped, a duplicated and an out-of-order frame replays
//      without a crash, a timeout or an id switch.
// "Exactly" in (a): for every OBJECTS message of the recording, the replay
// has one with the same capture utime and frame index, and the same objects
// in the same order with equal ids, states and float fields (bit-equal
// positions, velocities, since_seen_s, areas). Only header.utime (publish
// time) and header.seq may differ.

#include <unistd.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <mutex>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>

#include "common/lcm/bus.h"
#include "common/lcm/channels.h"
#include "ephor/shepherd_ground_truth_t.hpp"
#include "ephor/shepherd_objects_t.hpp"
#include "tests/integration/harness.h"

namespace ephor::testing {
namespace {

namespace fs = std::filesystem;
using std::chrono::seconds;

constexpr int kRecordedObjects = 120;  // OBJECTS messages recorded (4 s at 30 Hz)
constexpr int kSettledFrames = 45;     // 1.5 s at 30 Hz

struct Event {
  int64_t timestamp = 0;
  std::string channel;
  std::vector<uint8_t> data;
};

std::vector<Event> read_log(const std::string& path) {
  std::vector<Event> events;
  lcm::LogFile log(path, "r");
  EXPECT_TRUE(log.good()) << path;
  if (!log.good()) return events;
  while (const lcm::LogEvent* e = log.readNextEvent()) {
    const auto* p = static_cast<const uint8_t*>(e->data);
    events.push_back({e->timestamp, e->channel, std::vector<uint8_t>(p, p + e->datalen)});
  }
  return events;
}

void write_log(const std::string& path, const std::vector<Event>& events) {
  lcm::LogFile log(path, "w");
  ASSERT_TRUE(log.good()) << path;
  for (const auto& ev : events) {
    lcm::LogEvent e{};
    e.timestamp = ev.timestamp;
    e.channel = ev.channel;
    e.datalen = static_cast<int32_t>(ev.data.size());
    e.data = const_cast<uint8_t*>(ev.data.data());
    ASSERT_EQ(log.writeEvent(&e), 0);
  }
}

template <class T>
std::vector<T> decode_all(const std::vector<Event>& events, const std::string& channel) {
  std::vector<T> out;
  for (const auto& e : events) {
    if (e.channel != channel) continue;
    T m;
    if (m.decode(e.data.data(), 0, static_cast<int>(e.data.size())) ==
        static_cast<int>(e.data.size()))
      out.push_back(m);
  }
  return out;
}

std::string bytes_of(const std::string& path) {
  std::string out;
  if (FILE* f = std::fopen(path.c_str(), "rb")) {
    char buf[65536];
    size_t n = 0;
    while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) out.append(buf, n);
    std::fclose(f);
  }
  return out;
}

// Records every message on the default LCM URL (inside the namespace) to a log.
class Recorder {
 public:
  explicit Recorder(const std::string& path) : lcm_(resolve_lcm_url("")), log_(path, "w") {
    lcm_.subscribeFunction<Recorder*>(".*", &Recorder::on_message, this);
    thread_ = std::thread([this] {
      while (running_) lcm_.handleTimeout(50);
    });
  }
  ~Recorder() { stop(); }
  void stop() {
    running_ = false;
    if (thread_.joinable()) thread_.join();
  }
  int objects() const { return objects_; }

 private:
  static void on_message(const lcm::ReceiveBuffer* rbuf, const std::string& channel,
                         Recorder* self) {
    lcm::LogEvent e{};
    e.timestamp = rbuf->recv_utime;
    e.channel = channel;
    e.datalen = static_cast<int32_t>(rbuf->data_size);
    e.data = rbuf->data;
    self->log_.writeEvent(&e);
    if (channel == channels::kObjects) ++self->objects_;
  }
  lcm::LCM lcm_;
  lcm::LogFile log_;
  std::atomic<bool> running_{true};
  std::atomic<int> objects_{0};
  std::thread thread_;
};

// Scores OBJECTS against the logged GROUND_TRUTH of the same utime, in image px.
struct TruthScore {
  int frames = 0;        // OBJECTS paired with a GROUND_TRUTH
  int sheep_frames = 0;  // visible sheep away from the field edge
  int tracked = 0;       // ... with a visible object within 5 px
  double max_error_px = 0.0;
  double sum_error_px = 0.0;
  int over_1px = 0;              // tracked sheep-frames with an error above 1 px
  int settled_sheep_frames = 0;  // visible sheep-frames of settled sheep (see score())
  int settled_frames = 0;        // ... tracked
  double settled_max_error_px = 0.0;
  int id_switches = 0;
};

TruthScore score(const std::vector<shepherd_objects_t>& objects,
                 const std::vector<shepherd_ground_truth_t>& truth) {
  std::map<int64_t, const shepherd_ground_truth_t*> by_utime;
  for (const auto& t : truth) by_utime[t.utime] = &t;
  TruthScore s;
  std::map<int, int> id_of;        // sim sheep id -> object id
  std::map<int, int> visible_run;  // sim sheep id -> paired frames visible in a row
  bool first = true;
  for (const auto& objs : objects) {
    const auto it = by_utime.find(objs.utime);
    if (it == by_utime.end()) continue;
    ++s.frames;
    for (const auto& sheep : it->second->sheep) {
      if (!sheep.on_field || !sheep.visible) {
        visible_run[sheep.id] = 0;
        continue;
      }
      // Visible since the recording started, or for 1.5 s: its track has
      // settled (a mark coming out from under the arm is first seen partly
      // hidden, and a new track's filter starts from those frames).
      int& run = visible_run.try_emplace(sheep.id, first ? kSettledFrames : 0).first->second;
      const bool settled = ++run > kSettledFrames;
      if (sheep.x_mm < 30 || sheep.y_mm < 30 || sheep.x_mm > 1189 || sheep.y_mm > 884) continue;
      ++s.sheep_frames;
      s.settled_sheep_frames += settled;
      const shepherd_object_t* best = nullptr;
      double best_d = 1e9;
      for (const auto& o : objs.objects) {
        if (o.state != shepherd_object_t::STATE_VISIBLE) continue;
        const double d = std::hypot(o.u - sheep.u, o.v - sheep.v);
        if (d < best_d) {
          best_d = d;
          best = &o;
        }
      }
      if (best == nullptr || best_d > 5.0) continue;
      ++s.tracked;
      s.max_error_px = std::max(s.max_error_px, best_d);
      s.sum_error_px += best_d;
      s.over_1px += best_d > 1.0;
      if (settled) {
        ++s.settled_frames;
        s.settled_max_error_px = std::max(s.settled_max_error_px, best_d);
      }
      auto [known, inserted] = id_of.emplace(sheep.id, best->id);
      if (!inserted && known->second != best->id) {
        ++s.id_switches;
        known->second = best->id;
      }
    }
    first = false;
  }
  return s;
}

class ReplayTest : public ::testing::Test {
 protected:
  // Records the run once for all tests.
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("ephor_replay_" + std::to_string(getpid()));
    fs::create_directories(dir_);
    recorded_ = (dir_ / "run.lcm").string();
    Recorder recorder(recorded_);
    Processes procs;
    const std::vector<std::pair<std::string, std::string>> env = {{"EPHOR_HOST", "testhost"}};
    procs.start("sim", bin("ephor-sim"),
                {"--no-mlock", "--name", "sim", "--sheep", "4", "--seed", "3",
                 // The 30 mm/s stress speed: this test wants sheep that cross the arm's
                 // reach and the image within its seconds (at the 8 mm/s default they barely move).
                 "--speed-mm-s", "30"},
                env);
    procs.start("vision", bin("ephor-vision"), {"--no-mlock", "--name", "vision"}, env);
    procs.start("worldmodel", bin("ephor-worldmodel"), {"--no-mlock", "--name", "worldmodel"}, env);
    record_ok_ = wait_until([&] { return recorder.objects() >= kRecordedObjects; }, seconds(30));
    procs.stop_all();
    recorder.stop();
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }

  // Runs ephor-replay; returns its exit status (-1 when it did not finish).
  static int replay(const std::vector<std::string>& args,
                    std::vector<std::string>* lines = nullptr) {
    Processes p;
    p.start("replay", bin("ephor-replay"), args);
    if (!wait_until([&] { return !p.exits().empty(); }, seconds(120))) return -1;
    if (lines != nullptr) *lines = p.lines("replay");
    const auto e = p.exits().front();
    return e.signaled ? 128 + e.code : e.code;
  }

  static fs::path dir_;
  static std::string recorded_;
  static bool record_ok_;
};
fs::path ReplayTest::dir_;
std::string ReplayTest::recorded_;
bool ReplayTest::record_ok_ = false;

TEST_F(ReplayTest, ReproducesTheRecordedTracksExactlyAndIdenticallyTwice) {
  ASSERT_TRUE(record_ok_) << "the live run did not produce " << kRecordedObjects << " OBJECTS";
  const std::string out1 = (dir_ / "replay1.lcm").string(), out2 = (dir_ / "replay2.lcm").string();
  ASSERT_EQ(replay({recorded_, "--procs", "vision,worldmodel", "--only-processed", "--out", out1}),
            0);
  ASSERT_EQ(replay({recorded_, "--procs", "vision,worldmodel", "--only-processed", "--out", out2}),
            0);
  EXPECT_TRUE(bytes_of(out1) == bytes_of(out2)) << "two replays of one log differ";

  const auto recorded = decode_all<shepherd_objects_t>(read_log(recorded_), channels::kObjects);
  const auto replayed = decode_all<shepherd_objects_t>(read_log(out1), channels::kObjects);
  std::map<int64_t, const shepherd_objects_t*> replayed_at;
  for (const auto& m : replayed) replayed_at[m.utime] = &m;
  ASSERT_GE(recorded.size(), static_cast<size_t>(kRecordedObjects));
  int equal = 0, objects = 0;
  for (const auto& rec : recorded) {
    const auto it = replayed_at.find(rec.utime);
    ASSERT_NE(it, replayed_at.end()) << "no replayed OBJECTS for frame " << rec.frame_index;
    const shepherd_objects_t& rep = *it->second;
    EXPECT_EQ(rep.frame_index, rec.frame_index);
    ASSERT_EQ(rep.num_objects, rec.num_objects) << "frame " << rec.frame_index;
    for (int i = 0; i < rec.num_objects; ++i) {
      const shepherd_object_t& a = rec.objects[i];
      const shepherd_object_t& b = rep.objects[i];
      const bool same = a.id == b.id && a.state == b.state && a.u == b.u && a.v == b.v &&
                        a.x_mm == b.x_mm && a.y_mm == b.y_mm && a.vu_px_s == b.vu_px_s &&
                        a.vv_px_s == b.vv_px_s && a.vx_mm_s == b.vx_mm_s &&
                        a.vy_mm_s == b.vy_mm_s && a.since_seen_s == b.since_seen_s &&
                        a.area == b.area;
      EXPECT_TRUE(same) << "frame " << rec.frame_index << " object " << a.id << ": recorded ("
                        << a.u << ", " << a.v << ") replayed id " << b.id << " (" << b.u << ", "
                        << b.v << ")";
      equal += same;
      ++objects;
    }
  }
  std::printf("%zu recorded OBJECTS, %d objects compared, %d bit-equal\n", recorded.size(), objects,
              equal);
  EXPECT_EQ(equal, objects);
}

TEST_F(ReplayTest, ReplayedTracksMeetTheTrackingTargetsAgainstGroundTruth) {
  ASSERT_TRUE(record_ok_);
  const std::string out = (dir_ / "replay_all.lcm").string();
  ASSERT_EQ(replay({recorded_, "--procs", "vision,worldmodel", "--out", out}), 0);
  const auto log = read_log(recorded_);
  const auto truth = decode_all<shepherd_ground_truth_t>(log, channels::kGroundTruth);
  const auto replayed = decode_all<shepherd_objects_t>(read_log(out), channels::kObjects);
  const TruthScore s = score(replayed, truth);
  std::printf(
      "replayed %zu OBJECTS, %d paired with ground truth; visible sheep-frames %d, tracked %d, "
      "error mean %.3f px max %.3f px (%d above 1 px); settled tracks: %d sheep-frames, max "
      "%.3f px; id switches %d\n",
      replayed.size(), s.frames, s.sheep_frames, s.tracked,
      s.tracked > 0 ? s.sum_error_px / s.tracked : -1.0, s.max_error_px, s.over_1px,
      s.settled_frames, s.settled_max_error_px, s.id_switches);
  EXPECT_GE(s.frames, kRecordedObjects);
  EXPECT_GT(s.sheep_frames, 3 * kRecordedObjects);  // 4 sheep, most of them away from the edge
  EXPECT_EQ(s.id_switches, 0);
  // Every object reported visible is within 1 px of its sheep. A mark coming
  // out from under the arm (ground truth calls it visible from half shown)
  // is reported obscured until nearly whole (ephor-worldmodel
  // --mark-diameter-mm): its centroid is off by up to the mark's radius
  // until then. Settled sheep (visible 1.5 s, or since the start) are all
  // tracked; all visible sheep nearly all.
  EXPECT_LE(s.max_error_px, 1.0);
  EXPECT_EQ(s.settled_frames, s.settled_sheep_frames);
  EXPECT_GT(s.settled_frames, 2 * kRecordedObjects);
  EXPECT_GE(s.tracked, 0.9 * s.sheep_frames);
  EXPECT_LT(s.sum_error_px / s.tracked, 0.3);
}

TEST_F(ReplayTest, DroppedDuplicatedAndReorderedFramesAreHandled) {
  ASSERT_TRUE(record_ok_);
  auto events = read_log(recorded_);
  std::vector<size_t> frames;
  for (size_t i = 0; i < events.size(); ++i)
    if (events[i].channel == channels::kCamera) frames.push_back(i);
  ASSERT_GE(frames.size(), 60u);
  // Frame 20 dropped, frame 30 sent twice, frames 40 and 41 swapped.
  std::vector<Event> damaged;
  for (size_t i = 0; i < events.size(); ++i) {
    if (i == frames[20]) continue;
    if (i == frames[40]) {
      damaged.push_back(events[frames[41]]);
      damaged.push_back(events[frames[40]]);
      continue;
    }
    if (i == frames[41]) continue;
    damaged.push_back(events[i]);
    if (i == frames[30]) damaged.push_back(events[i]);
  }
  const std::string path = (dir_ / "damaged.lcm").string();
  write_log(path, damaged);
  const std::string out = (dir_ / "replay_damaged.lcm").string();
  std::vector<std::string> lines;
  ASSERT_EQ(replay({path, "--procs", "vision,worldmodel", "--out", out}, &lines), 0)
      << "a process died or a frame timed out";
  const auto replayed = decode_all<shepherd_objects_t>(read_log(out), channels::kObjects);
  const auto blobs = read_log(out);
  int blob_msgs = 0;
  for (const auto& e : blobs) blob_msgs += e.channel == channels::kBlobs;
  // Every fed frame (one dropped, one twice) has its BLOBS; the duplicate and
  // the late frame get no OBJECTS.
  EXPECT_EQ(blob_msgs, static_cast<int>(frames.size()));
  EXPECT_EQ(replayed.size(), frames.size() - 2);
  const TruthScore s =
      score(replayed, decode_all<shepherd_ground_truth_t>(events, channels::kGroundTruth));
  std::printf(
      "damaged log: %zu OBJECTS; tracked %d of %d sheep-frames, max error %.3f px, %d id "
      "switches\n",
      replayed.size(), s.tracked, s.sheep_frames, s.max_error_px, s.id_switches);
  EXPECT_EQ(s.id_switches, 0);
  EXPECT_EQ(s.settled_frames, s.settled_sheep_frames);
  EXPECT_GE(s.tracked, 0.9 * s.sheep_frames);
}

}  // namespace
}  // namespace ephor::testing
