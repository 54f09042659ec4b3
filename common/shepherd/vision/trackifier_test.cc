#include "common/shepherd/vision/trackifier.h"

#include <gtest/gtest.h>

#include "common/shepherd/vision/synthetic_image.h"

namespace ephor::vision {
namespace {

constexpr uint8_t kThr = 120;

TrackifierConfig no_fallback() {
  TrackifierConfig c;
  c.full_every = 0;
  return c;
}

ImageView frame(SyntheticImage& img, std::initializer_list<std::pair<double, double>> discs) {
  img.fill(20.0f);
  for (const auto& [u, v] : discs) img.add_disc(u, v, 8.0, 220.0f);
  return img.render();
}

TEST(TrackifierTest, FollowsAMovingBlobWithoutAFullSearch) {
  SyntheticImage img(256, 200, 20.0f);
  Blobifier b;
  Trackifier t(no_fallback());
  ASSERT_EQ(t.track(b, frame(img, {{100.0, 100.0}}), kThr, ScanMode::kFull).size(), 1u);
  EXPECT_TRUE(t.last_was_full());
  for (int i = 1; i <= 10; ++i) {
    const double u = 100.0 + 2.5 * i, v = 100.0 - 1.5 * i;  // 2.9 px per frame
    const auto& blobs = t.track(b, frame(img, {{u, v}}), kThr, ScanMode::kFull);
    EXPECT_FALSE(t.last_was_full());
    ASSERT_EQ(blobs.size(), 1u) << "frame " << i;
    EXPECT_NEAR(blobs[0].u, u, 0.2);
    EXPECT_NEAR(blobs[0].v, v, 0.2);
  }
}

TEST(TrackifierTest, RegrowsFromANearbyPixelWhenTheCentroidIsDark) {
  // A ring-like mark: its centre is dark, its body is near the old centroid.
  SyntheticImage img(128, 128, 20.0f);
  Blobifier b;
  Trackifier t(no_fallback());
  t.track(b, frame(img, {{60.0, 60.0}}), kThr, ScanMode::kFull);
  img.fill(20.0f);
  img.add_disc(60.0, 60.0, 8.0, 220.0f);
  img.add_disc(60.0, 60.0, 2.0, 20.0f);  // hole at the centre
  const auto& blobs = t.track(b, img.render(), kThr, ScanMode::kFull);
  ASSERT_EQ(blobs.size(), 1u);
  EXPECT_NEAR(blobs[0].u, 60.0, 0.2);
}

TEST(TrackifierTest, FindsANewBlobEnteringAtTheBorder) {
  SyntheticImage img(256, 200, 20.0f);
  Blobifier b;
  Trackifier t(no_fallback());
  t.track(b, frame(img, {{100.0, 100.0}}), kThr, ScanMode::kFull);
  // Half a mark at the right edge and one at the top edge.
  const auto& blobs =
      t.track(b, frame(img, {{100.0, 100.0}, {254.0, 60.0}, {150.0, 3.0}}), kThr, ScanMode::kFull);
  EXPECT_FALSE(t.last_was_full());
  ASSERT_EQ(blobs.size(), 3u);
  int at_right = 0, at_top = 0;
  for (const Blob& bl : blobs) {
    if (bl.u_max == 255) ++at_right;
    if (bl.v_min == 0) ++at_top;
  }
  EXPECT_EQ(at_right, 1);
  EXPECT_EQ(at_top, 1);
}

TEST(TrackifierTest, InteriorNewcomerWaitsForTheFullSearch) {
  // Documented: trackify sees only old blobs and the border band; the
  // periodic full blobify (every 3rd frame here) picks up the rest.
  SyntheticImage img(256, 200, 20.0f);
  Blobifier b;
  TrackifierConfig cfg;
  cfg.full_every = 3;
  Trackifier t(cfg);
  EXPECT_EQ(t.track(b, frame(img, {{100.0, 100.0}}), kThr, ScanMode::kFull).size(), 1u);  // full
  const auto two = {std::pair{100.0, 100.0}, std::pair{180.0, 120.0}};
  EXPECT_EQ(t.track(b, frame(img, two), kThr, ScanMode::kFull).size(), 1u);
  EXPECT_EQ(t.track(b, frame(img, two), kThr, ScanMode::kFull).size(), 1u);
  EXPECT_EQ(t.track(b, frame(img, two), kThr, ScanMode::kFull).size(), 2u);  // full
  EXPECT_TRUE(t.last_was_full());
  EXPECT_EQ(t.track(b, frame(img, two), kThr, ScanMode::kFull).size(), 2u);  // tracked
  EXPECT_FALSE(t.last_was_full());
}

TEST(TrackifierTest, RequestFullSearchesTheWholeImage) {
  SyntheticImage img(256, 200, 20.0f);
  Blobifier b;
  Trackifier t(no_fallback());
  t.track(b, frame(img, {{100.0, 100.0}}), kThr, ScanMode::kFull);
  t.request_full();
  EXPECT_EQ(t.track(b, frame(img, {{100.0, 100.0}, {180.0, 120.0}}), kThr, ScanMode::kFull).size(),
            2u);
  EXPECT_TRUE(t.last_was_full());
}

TEST(TrackifierTest, MergedBlobsAreReportedOnce) {
  SyntheticImage img(256, 200, 20.0f);
  Blobifier b;
  Trackifier t(no_fallback());
  ASSERT_EQ(t.track(b, frame(img, {{100.0, 100.0}, {120.0, 100.0}}), kThr, ScanMode::kFull).size(),
            2u);
  // Both move onto one another: one blob, both old centroids inside it.
  EXPECT_EQ(t.track(b, frame(img, {{104.0, 100.0}, {116.0, 100.0}}), kThr, ScanMode::kFull).size(),
            1u);
  EXPECT_EQ(t.track(b, frame(img, {{104.0, 100.0}, {116.0, 100.0}}), kThr, ScanMode::kAxis).size(),
            1u);
}

TEST(TrackifierTest, AxisScanTracksToo) {
  SyntheticImage img(256, 200, 20.0f);
  Blobifier b;
  Trackifier t(no_fallback());
  t.track(b, frame(img, {{100.3, 100.6}}), kThr, ScanMode::kAxis);
  const auto& blobs = t.track(b, frame(img, {{102.3, 101.6}}), kThr, ScanMode::kAxis);
  ASSERT_EQ(blobs.size(), 1u);
  EXPECT_NEAR(blobs[0].u, 102.3, 0.25);
  EXPECT_NEAR(blobs[0].v, 101.6, 0.25);
}

TEST(TrackifierTest, RejectsBadConfig) {
  TrackifierConfig c;
  c.band_px = 0;
  EXPECT_THROW(Trackifier{c}, std::invalid_argument);
}

}  // namespace
}  // namespace ephor::vision
