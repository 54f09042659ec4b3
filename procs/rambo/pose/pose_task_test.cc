// PoseFrameQueue (pose_task.h): the pose process's frame queue on utimes
// that the bus can carry but a clock never gives.
#include "procs/rambo/pose/pose_task.h"

#include <cstdint>
#include <limits>
#include <optional>

#include <gtest/gtest.h>

namespace ephor::rambo {
namespace {

// A frame captured 1.8e19 us after the only arm state: the difference
// overflowed int64_t (undefined; wrapped negative, it passed for "within
// 50 ms" and the frame took the camera pose of a state from 5e5 years
// before). The frame now has no camera pose.
TEST(PoseFrameQueue, AFrameFarAfterTheLastStateHasNoCameraPose) {
  PoseFrameQueue frames(5);
  const int64_t early = std::numeric_limits<int64_t>::min() + 1;
  const int64_t late = std::numeric_limits<int64_t>::max() - 1;
  EXPECT_FALSE(frames.on_arm_state(early, arm::Joints::Zero()));
  EXPECT_FALSE(frames.joints_at(late).has_value());
  EXPECT_TRUE(frames.joints_at(early).has_value());
  rambo_features_t f{};
  f.utime = late;
  EXPECT_FALSE(frames.on_features(f));  // waits for a state at or after it
  f.utime = late - 1;
  EXPECT_TRUE(frames.on_features(f));  // the waiting one goes as it is
  const std::optional<ReadyFrame> r = frames.take();
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->features.utime, late);
  EXPECT_FALSE(r->q.has_value());
}

// Between two states far apart, the joints are interpolated without
// overflow: halfway in time, halfway in angle.
TEST(PoseFrameQueue, InterpolationBetweenStatesFarApart) {
  PoseFrameQueue frames(5);
  const int64_t a = -9'000'000'000'000'000'000;
  const int64_t b = 9'000'000'000'000'000'000;
  frames.on_arm_state(a, arm::Joints::Zero());
  frames.on_arm_state(b, arm::Joints::Constant(1.0));
  const std::optional<arm::Joints> q = frames.joints_at(0);
  ASSERT_TRUE(q.has_value());
  EXPECT_NEAR((*q)[0], 0.5, 1e-9);
}

}  // namespace
}  // namespace ephor::rambo
