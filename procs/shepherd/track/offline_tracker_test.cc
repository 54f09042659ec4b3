#include "procs/shepherd/track/offline_tracker.h"

#include <random>
#include <stdexcept>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "common/shepherd/vision/synthetic_image.h"

namespace ephor::track {
namespace {

using vision::SyntheticImage;

// Two dark discs (radius 10 px) on a bright floor, moving at (+60, 0) and
// (0, +30) px/s from (60, 80) and (200, 40), with noise: frame i at t = i/30 s.
vision::ImageView frame(SyntheticImage& img, std::mt19937& rng, int i) {
  const double t = i / 30.0;
  img.fill(210.0f);
  img.add_disc(60.0 + 60.0 * t, 80.0, 10.0, 40.0f);
  img.add_disc(200.0, 40.0 + 30.0 * t, 10.0, 40.0f);
  return img.render(2.0, rng);
}

TEST(OfflineTrackerTest, DarkObjectsOnABrightFloorKeepTheirIdsAndVelocities) {
  OfflineTrackerConfig cfg;
  cfg.vision.foreground.mode = vision::ForegroundMode::kDark;
  OfflineTracker tracker(cfg);
  SyntheticImage img(320, 240, 210.0f);
  std::mt19937 rng(11);
  FrameTracks last;
  for (int i = 0; i < 60; ++i) {
    last = tracker.process(frame(img, rng, i), i, i / 30.0);
    ASSERT_EQ(last.tracks.size(), 2u) << "frame " << i;
    EXPECT_EQ(last.tracks[0].id, 1);
    EXPECT_EQ(last.tracks[1].id, 2);
  }
  const double t = 59 / 30.0;
  // Ids follow the order blobs are found in the first frame: top row first.
  const auto& a = last.tracks[1];
  const auto& b = last.tracks[0];
  EXPECT_EQ(a.state, worldmodel::ObjectState::kVisible);
  EXPECT_NEAR(a.x, 60.0 + 60.0 * t, 0.5);
  EXPECT_NEAR(a.y, 80.0, 0.5);
  EXPECT_NEAR(a.vx, 60.0, 3.0);
  EXPECT_NEAR(a.vy, 0.0, 3.0);
  EXPECT_NEAR(b.x, 200.0, 0.5);
  EXPECT_NEAR(b.y, 40.0 + 30.0 * t, 0.5);
  EXPECT_NEAR(b.vy, 30.0, 3.0);
  EXPECT_EQ(tracker.counters()->objects_created, 2);
}

TEST(OfflineTrackerTest, MotionModeFindsMovingObjectsOnly) {
  OfflineTrackerConfig cfg;
  cfg.vision.foreground = {vision::ForegroundMode::kMotion, 0.05, 2};
  cfg.settings.threshold = 40;
  OfflineTracker tracker(cfg);
  SyntheticImage img(320, 240, 210.0f);
  std::mt19937 rng(12);
  // A still dark square that motion must ignore, plus the two moving discs.
  FrameTracks last;
  for (int i = 0; i < 45; ++i) {
    img.fill(210.0f);
    img.add_rect(250, 180, 279, 209, 30.0f);
    const double t = i / 30.0;
    img.add_disc(60.0 + 60.0 * t, 80.0, 10.0, 40.0f);
    last = tracker.process(img.render(2.0, rng), i, t);
  }
  int visible = 0;
  for (const auto& tr : last.tracks) {
    if (tr.state != worldmodel::ObjectState::kVisible) continue;
    ++visible;
    EXPECT_NEAR(tr.y, 80.0, 2.0);
    EXPECT_NEAR(tr.vx, 60.0, 10.0);
  }
  EXPECT_EQ(visible, 1);
}

TEST(OfflineTrackerTest, JsonLineHasTheDocumentedFields) {
  FrameTracks f;
  f.frame = 7;
  f.t_s = 0.25;
  f.tracks.push_back({3, 10.5, 20.0, -1.0, 2.0, worldmodel::ObjectState::kObscured});
  const auto j = nlohmann::json::parse(to_json_line(f));
  EXPECT_EQ(j["frame"], 7);
  EXPECT_DOUBLE_EQ(j["t"].get<double>(), 0.25);
  ASSERT_EQ(j["tracks"].size(), 1u);
  EXPECT_EQ(j["tracks"][0]["id"], 3);
  EXPECT_DOUBLE_EQ(j["tracks"][0]["x"].get<double>(), 10.5);
  EXPECT_DOUBLE_EQ(j["tracks"][0]["vy"].get<double>(), 2.0);
  EXPECT_EQ(j["tracks"][0]["state"], "obscured");
  EXPECT_EQ(to_json_line(f).find('\n'), std::string::npos);
}

TEST(OfflineTrackerTest, BadFramesAreNamed) {
  OfflineTracker tracker({});
  SyntheticImage a(100, 80, 20.0f), b(120, 80, 20.0f);
  tracker.process(a.render(), 0, 0.0);
  try {
    tracker.process(b.render(), 1, 0.1);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("120 x 80"), std::string::npos) << e.what();
  }
  EXPECT_THROW(tracker.process(a.render(), 2, 0.0), std::invalid_argument);  // time went back
  EXPECT_THROW(tracker.process(vision::ImageView{}, 3, 0.2), std::invalid_argument);
}

}  // namespace
}  // namespace ephor::track
