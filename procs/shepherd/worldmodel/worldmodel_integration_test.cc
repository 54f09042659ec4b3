// ephor-worldmodel as a process, in a private network namespace: blobs in on
// BLOBS, objects out on OBJECTS with stable ids and the frame's utime; a
// malformed message does not stop it.

#include <mutex>
#include <optional>

#include <gtest/gtest.h>

#include "common/lcm/bus.h"
#include "common/lcm/channels.h"
#include "ephor/shepherd_blobs_t.hpp"
#include "ephor/shepherd_objects_t.hpp"
#include "tests/integration/harness.h"

namespace ephor::testing {
namespace {

using std::chrono::seconds;

class ObjectsProbe {
 public:
  ObjectsProbe() : bus_("", "probe") {
    bus_.subscribe<shepherd_objects_t>(channels::kObjects, [this](const shepherd_objects_t& m) {
      std::lock_guard<std::mutex> lock(mutex_);
      last_ = m;
      ++count_;
    });
    bus_.start();
  }
  std::optional<shepherd_objects_t> last() {
    std::lock_guard<std::mutex> lock(mutex_);
    return last_;
  }
  int count() {
    std::lock_guard<std::mutex> lock(mutex_);
    return count_;
  }
  Bus& bus() { return bus_; }

 private:
  Bus bus_;
  std::mutex mutex_;
  std::optional<shepherd_objects_t> last_;
  int count_ = 0;
};

shepherd_blobs_t frame(int64_t index, double t_s) {
  shepherd_blobs_t m{};
  m.utime = 1'000'000 + index * 33'333;
  m.frame_index = index;
  for (const auto& [u0, v0, vu] : {std::tuple{150.0, 200.0, 11.0}, {300.0, 300.0, -11.0}}) {
    shepherd_blob_t b{};
    b.u = static_cast<float>(u0 + vu * t_s);
    b.v = static_cast<float>(v0);
    b.area = 200;
    m.blobs.push_back(b);
  }
  m.num_blobs = static_cast<int32_t>(m.blobs.size());
  return m;
}

TEST(WorldModelProcess, PublishesObjectsWithStableIdsAndSurvivesGarbage) {
  ObjectsProbe probe;
  Processes procs;
  procs.start("worldmodel", bin("ephor-worldmodel"), {"--no-mlock"},
              {{"EPHOR_PROCESS", "worldmodel"}, {"EPHOR_HOST", "testhost"}});
  // The process is up when it answers a frame (retransmit until it does).
  ASSERT_TRUE(wait_until(
      [&] {
        auto m = frame(0, 0.0);
        probe.bus().publish(channels::kBlobs, m);
        return probe.count() > 0;
      },
      seconds(15)))
      << "no OBJECTS from ephor-worldmodel";

  const uint8_t garbage[] = {1, 2, 3, 4, 5};
  probe.bus().publish_raw(channels::kBlobs, garbage, sizeof garbage);

  // One frame at a time, each answered before the next (the mailbox keeps
  // only the newest, so a burst would be merged).
  for (int64_t i = 1; i <= 60; ++i) {
    auto m = frame(i, static_cast<double>(i) / 30.0);
    const int before = probe.count();
    probe.bus().publish(channels::kBlobs, m);
    ASSERT_TRUE(wait_until([&] { return probe.count() > before; }, seconds(5))) << "frame " << i;
  }
  const auto last = probe.last();
  ASSERT_TRUE(last);
  EXPECT_EQ(last->utime, 1'000'000 + 60 * 33'333);
  EXPECT_EQ(last->frame_index, 60);
  ASSERT_EQ(last->num_objects, 2);
  for (const auto& o : last->objects) {
    EXPECT_EQ(o.state, int8_t{shepherd_object_t::STATE_VISIBLE});
    // Object 1 is the sheep that started at u = 150 and moves right.
    if (o.id == 1) {
      EXPECT_NEAR(o.u, 150.0 + 22.0, 0.5);
      EXPECT_NEAR(o.vu_px_s, 11.0, 1.0);
      EXPECT_GT(o.vx_mm_s, 25.0);
    } else {
      EXPECT_EQ(o.id, 2);
      EXPECT_NEAR(o.vu_px_s, -11.0, 1.0);
    }
  }
  EXPECT_TRUE(procs.exits().empty()) << "ephor-worldmodel exited";
}

}  // namespace
}  // namespace ephor::testing
