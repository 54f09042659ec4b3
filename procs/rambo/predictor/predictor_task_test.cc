// PoseFitter (predictor_task.h): the predictor's fit task on RAMBO_POSE
// streams that its fuzz target (rambo_predictor) found faults with.
#include "procs/rambo/predictor/predictor_task.h"

#include <cmath>
#include <optional>

#include <gtest/gtest.h>

namespace ephor::rambo {
namespace {

constexpr int64_t kT0 = 1'700'000'000'000'000;  // us

// A found pose of a target drifting along x at 30 mm/s, at t0 + k 200 ms.
rambo_pose_t pose_at(int k) {
  rambo_pose_t p{};
  p.utime = kT0 + 200'000 * k;
  p.found = true;
  p.rms_reprojection_px = 0.6;
  p.target_r[0] = p.target_r[4] = p.target_r[8] = 1.0;
  p.target_t_mm[0] = 900.0 + 6.0 * k;
  p.target_t_mm[2] = 100.0;
  return p;
}

bool finite_prediction(const rambo_prediction_t& p) {
  for (int k = 0; k < 3; ++k)
    if (!std::isfinite(p.position_mm[k]) || !std::isfinite(p.velocity_mm_s[k])) return false;
  return std::isfinite(p.position_sigma_mm) && std::isfinite(p.rotation_sigma_rad) &&
         p.position_sigma_mm >= 0.0 && p.rotation_sigma_rad >= 0.0;
}

// The fuzz target's crash: a first pose 1e304 mm below the base (finite, a
// bad message) was fitted with four good ones into a prediction 2e303 mm
// away with an infinite position sigma, which the pose process and the
// planner would have taken. It is dropped now, and the good ones fit.
TEST(PoseFitter, APoseFarOutsideTheWorkcellIsDropped) {
  PoseFitter fitter(PoseFitterOptions{});
  rambo_pose_t far = pose_at(0);
  far.target_t_mm[2] = -1.02865e304;
  EXPECT_FALSE(fitter.on_pose(far, kT0).has_value());
  EXPECT_EQ(fitter.dropped(), 1);
  std::optional<rambo_prediction_t> out;
  for (int k = 1; k <= 5; ++k) out = fitter.on_pose(pose_at(k), kT0 + 200'000 * k);
  ASSERT_TRUE(out.has_value());
  EXPECT_TRUE(out->fitted) << out->reason;
  EXPECT_TRUE(finite_prediction(*out));
  EXPECT_NEAR(out->position_mm[0], 930.0, 1.0);
  EXPECT_EQ(fitter.fits(), 1);
}

// A pose a minute after the last starts the fit afresh (the old fit is not
// integrated across the gap): the window holds it alone.
TEST(PoseFitter, APoseLongAfterTheLastStartsAfresh) {
  PoseFitter fitter(PoseFitterOptions{});
  for (int k = 0; k < 6; ++k) fitter.on_pose(pose_at(k), kT0);
  ASSERT_EQ(fitter.fits(), 2);
  rambo_pose_t later = pose_at(6);
  later.utime += static_cast<int64_t>(PoseFitter::kMaxGapS * 1e6) + 1;
  const std::optional<rambo_prediction_t> out = fitter.on_pose(later, kT0);
  ASSERT_TRUE(out.has_value());
  EXPECT_FALSE(out->fitted);
  EXPECT_EQ(out->samples, 1);
  EXPECT_EQ(out->reason, "waiting for 5 poses");
  EXPECT_EQ(fitter.dropped(), 0);
}

}  // namespace
}  // namespace ephor::rambo
