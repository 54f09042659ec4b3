#include "common/shepherd/vision/blobifier.h"

#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "common/shepherd/vision/synthetic_image.h"

namespace ephor::vision {
namespace {

constexpr uint8_t kThr = 100;

BlobifierConfig with_k(int k, int min_area = 10) {
  BlobifierConfig c;
  c.sample_step = k;
  c.min_area = min_area;
  return c;
}

TEST(BlobifierTest, RectangleCentroidAreaAndBox) {
  SyntheticImage img(64, 48, 10.0f);
  img.add_rect(10, 20, 19, 24, 200.0f);  // 10 x 5 px
  Blobifier b(with_k(4));
  const auto& blobs = b.blobify(img.render(), kThr, ScanMode::kFull);
  ASSERT_EQ(blobs.size(), 1u);
  EXPECT_EQ(blobs[0].area, 50);
  EXPECT_FLOAT_EQ(blobs[0].u, 14.5f);  // (10 + 19) / 2
  EXPECT_FLOAT_EQ(blobs[0].v, 22.0f);  // (20 + 24) / 2
  EXPECT_EQ(blobs[0].u_min, 10);
  EXPECT_EQ(blobs[0].u_max, 19);
  EXPECT_EQ(blobs[0].v_min, 20);
  EXPECT_EQ(blobs[0].v_max, 24);
}

TEST(BlobifierTest, LatticeDiscHasHandCountedArea) {
  // Pixels with (u-30)^2 + (v-20)^2 <= 25: 1 + 4*5 + 4*4 + 4*4 + ... = 81
  // lattice points in a radius-5 disc (Gauss circle problem, N(5) = 81).
  SyntheticImage img(64, 48, 10.0f);
  for (int v = 0; v < 48; ++v) {
    for (int u = 0; u < 64; ++u) {
      if ((u - 30) * (u - 30) + (v - 20) * (v - 20) <= 25) img.set(u, v, 220.0f);
    }
  }
  Blobifier b(with_k(4));
  const auto& blobs = b.blobify(img.render(), kThr, ScanMode::kFull);
  ASSERT_EQ(blobs.size(), 1u);
  EXPECT_EQ(blobs[0].area, 81);
  EXPECT_FLOAT_EQ(blobs[0].u, 30.0f);
  EXPECT_FLOAT_EQ(blobs[0].v, 20.0f);
  EXPECT_EQ(blobs[0].u_min, 25);
  EXPECT_EQ(blobs[0].u_max, 35);
}

TEST(BlobifierTest, AntialiasedDiscCentroidIsSubPixel) {
  // Threshold halfway between field and mark: the thresholded region is the
  // set of pixels more than half covered, centred on the true centre.
  SyntheticImage img(128, 96, 20.0f);
  img.add_disc(60.3, 40.7, 8.0, 220.0f);
  Blobifier b(with_k(4));
  const auto& blobs = b.blobify(img.render(), 120, ScanMode::kFull);
  ASSERT_EQ(blobs.size(), 1u);
  EXPECT_NEAR(blobs[0].u, 60.3f, 0.15f);
  EXPECT_NEAR(blobs[0].v, 40.7f, 0.15f);
  EXPECT_NEAR(blobs[0].area, 201, 10);  // pi * 8^2
}

TEST(BlobifierTest, BlobsTouchingEveryBorder) {
  SyntheticImage img(40, 30, 0.0f);
  img.add_rect(0, 0, 5, 3, 255.0f);      // top-left corner, 6 x 4
  img.add_rect(36, 10, 39, 13, 255.0f);  // right edge, 4 x 4
  img.add_rect(10, 27, 19, 29, 255.0f);  // bottom edge, 10 x 3
  Blobifier b(with_k(4));
  auto blobs = b.blobify(img.render(), kThr, ScanMode::kFull);
  ASSERT_EQ(blobs.size(), 3u);
  std::sort(blobs.begin(), blobs.end(), [](const Blob& a, const Blob& c) { return a.u < c.u; });
  EXPECT_EQ(blobs[0].area, 24);
  EXPECT_FLOAT_EQ(blobs[0].u, 2.5f);
  EXPECT_FLOAT_EQ(blobs[0].v, 1.5f);
  EXPECT_EQ(blobs[0].u_min, 0);
  EXPECT_EQ(blobs[0].v_min, 0);
  EXPECT_EQ(blobs[1].area, 30);
  EXPECT_FLOAT_EQ(blobs[1].v, 28.0f);
  EXPECT_EQ(blobs[1].v_max, 29);
  EXPECT_EQ(blobs[2].area, 16);
  EXPECT_FLOAT_EQ(blobs[2].u, 37.5f);
  EXPECT_EQ(blobs[2].u_max, 39);
}

TEST(BlobifierTest, TwoBlobsOneDarkColumnApartStaySeparate) {
  SyntheticImage img(64, 48, 10.0f);
  img.add_rect(10, 10, 19, 19, 200.0f);
  img.add_rect(21, 10, 30, 19, 200.0f);  // column 20 is dark
  Blobifier b(with_k(4));
  const auto& blobs = b.blobify(img.render(), kThr, ScanMode::kFull);
  ASSERT_EQ(blobs.size(), 2u);
  EXPECT_EQ(blobs[0].area, 100);
  EXPECT_EQ(blobs[1].area, 100);
}

TEST(BlobifierTest, DiagonalContactIsNotAConnection) {
  // 4-neighbour connectivity: squares that touch only at a corner are two blobs.
  SyntheticImage img(64, 48, 10.0f);
  img.add_rect(8, 8, 15, 15, 200.0f);
  img.add_rect(16, 16, 23, 23, 200.0f);
  Blobifier b(with_k(4));
  EXPECT_EQ(b.blobify(img.render(), kThr, ScanMode::kFull).size(), 2u);
}

TEST(BlobifierTest, ConcaveBlobIsFoundOnce) {
  // A U shape hit by many samples on both arms is still one blob.
  SyntheticImage img(64, 64, 10.0f);
  img.add_rect(8, 8, 15, 50, 200.0f);
  img.add_rect(40, 8, 47, 50, 200.0f);
  img.add_rect(8, 43, 47, 50, 200.0f);
  Blobifier b(with_k(4));
  const auto& blobs = b.blobify(img.render(), kThr, ScanMode::kFull);
  ASSERT_EQ(blobs.size(), 1u);
  EXPECT_EQ(blobs[0].area, 8 * 43 * 2 + 24 * 8);
}

TEST(BlobifierTest, NoisePixelsBelowMinAreaAreDropped) {
  SyntheticImage img(64, 48, 10.0f);
  for (int i = 0; i < 8; ++i) img.set(4 * i + 4, 8, 250.0f);  // single hot pixels on samples
  img.add_rect(40, 40, 42, 42, 250.0f);                       // 9 px < 10
  Blobifier b(with_k(4, 10));
  const auto& blobs = b.blobify(img.render(), kThr, ScanMode::kFull);
  EXPECT_TRUE(blobs.empty());
  EXPECT_EQ(b.stats().noise_blobs, 9);
}

TEST(BlobifierTest, BlobSmallerThanSampleStepIsFoundOnlyWhenASampleLandsOnIt) {
  // Documented behaviour: only grid samples (multiples of k) start a blob.
  SyntheticImage img(64, 48, 10.0f);
  img.add_rect(3, 3, 5, 5, 200.0f);  // 3 x 3 between samples 0 and 8
  Blobifier b(with_k(8, 1));
  EXPECT_TRUE(b.blobify(img.render(), kThr, ScanMode::kFull).empty());
  SyntheticImage img2(64, 48, 10.0f);
  img2.add_rect(7, 7, 9, 9, 200.0f);  // covers sample (8, 8)
  const auto& blobs = b.blobify(img2.render(), kThr, ScanMode::kFull);
  ASSERT_EQ(blobs.size(), 1u);
  EXPECT_EQ(blobs[0].area, 9);
}

TEST(BlobifierTest, BuffersAreReusedWithoutLeakingPreviousFrame) {
  SyntheticImage a(64, 48, 10.0f);
  a.add_rect(10, 10, 20, 20, 200.0f);
  SyntheticImage c(64, 48, 10.0f);
  c.add_rect(30, 30, 35, 35, 200.0f);
  Blobifier b(with_k(4));
  ASSERT_EQ(b.blobify(a.render(), kThr, ScanMode::kFull).size(), 1u);
  // Same pixels again: the marks of the last frame must not hide the blob.
  ASSERT_EQ(b.blobify(a.render(), kThr, ScanMode::kFull).size(), 1u);
  const auto& blobs = b.blobify(c.render(), kThr, ScanMode::kFull);
  ASSERT_EQ(blobs.size(), 1u);
  EXPECT_EQ(blobs[0].area, 36);
}

TEST(BlobifierTest, FrameStampWrapAroundDoesNotHideBlobs) {
  // Marks are stamped per frame in 16 bits; after 65535 frames the stamp
  // wraps and the marks are cleared once.
  SyntheticImage img(16, 16, 0.0f);
  img.add_rect(4, 4, 7, 7, 200.0f);
  const ImageView view = img.render();
  Blobifier b(with_k(4, 1));
  for (int i = 0; i < 70000; ++i) {
    if (b.blobify(view, kThr, ScanMode::kFull).size() != 1u) FAIL() << "frame " << i;
  }
}

TEST(BlobifierTest, HonoursStrideLargerThanWidth) {
  // A 20 x 10 window at column 8 of a 64-wide buffer.
  std::vector<uint8_t> buf(64 * 10, 0);
  for (int v = 2; v <= 5; ++v) {
    for (int u = 4; u <= 9; ++u) buf[static_cast<size_t>(v * 64 + 8 + u)] = 200;
  }
  buf[static_cast<size_t>(4 * 64 + 40)] = 255;  // outside the window
  ImageView view{buf.data() + 8, 20, 10, 64};
  Blobifier b(with_k(2, 1));
  const auto& blobs = b.blobify(view, kThr, ScanMode::kFull);
  ASSERT_EQ(blobs.size(), 1u);
  EXPECT_EQ(blobs[0].area, 24);
  EXPECT_FLOAT_EQ(blobs[0].u, 6.5f);
}

TEST(BlobifierTest, StopsAtMaxBlobs) {
  SyntheticImage img(64, 64, 0.0f);
  for (int i = 0; i < 5; ++i) img.add_rect(4 + 12 * i, 4, 8 + 12 * i, 8, 200.0f);
  BlobifierConfig c = with_k(4);
  c.max_blobs = 3;
  Blobifier b(c);
  EXPECT_EQ(b.blobify(img.render(), kThr, ScanMode::kFull).size(), 3u);
  EXPECT_TRUE(b.stats().truncated);
}

TEST(BlobifierTest, RejectsBadImageAndConfig) {
  Blobifier b;
  EXPECT_THROW(b.blobify(ImageView{nullptr, 10, 10, 10}, kThr, ScanMode::kFull),
               std::invalid_argument);
  uint8_t px[4] = {};
  EXPECT_THROW(b.blobify(ImageView{px, 4, 1, 2}, kThr, ScanMode::kFull), std::invalid_argument);
  EXPECT_THROW(Blobifier(with_k(0)), std::invalid_argument);
  EXPECT_THROW(Blobifier(with_k(4, 0)), std::invalid_argument);
}

TEST(BlobifierTest, AxisScanLocatesNoisyDiscWithinAQuarterPixel) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> frac(0.0, 1.0);
  double sq = 0.0;
  int n = 0;
  for (int i = 0; i < 20; ++i) {
    SyntheticImage img(96, 96, 30.0f);
    const double cu = 40.0 + frac(rng), cv = 50.0 + frac(rng);
    img.add_disc(cu, cv, 8.0, 210.0f);
    Blobifier b(with_k(4));
    const auto& blobs = b.blobify(img.render(3.0, rng), 165, ScanMode::kAxis);
    ASSERT_EQ(blobs.size(), 1u) << "disc " << i;
    EXPECT_EQ(b.stats().axis_fallbacks, 0);
    EXPECT_EQ(b.stats().pixels_filled, 0);  // no fill: only the three runs
    sq += std::pow(static_cast<double>(blobs[0].u) - cu, 2) +
          std::pow(static_cast<double>(blobs[0].v) - cv, 2);
    ++n;
    // Threshold 165 is 75 % of the way to the mark: the contour radius is
    // about 8 - 0.5 + ... px; area within 15 % of the filled count.
    EXPECT_NEAR(blobs[0].area, 180, 30);
  }
  EXPECT_LT(std::sqrt(sq / n), 0.25);
}

TEST(BlobifierTest, AxisScanFallsBackToFillForNonRoundBlob) {
  SyntheticImage img(64, 64, 10.0f);
  img.add_rect(10, 10, 40, 14, 200.0f);  // a long bar: diameters disagree
  Blobifier b(with_k(4));
  const auto& blobs = b.blobify(img.render(), kThr, ScanMode::kAxis);
  ASSERT_EQ(blobs.size(), 1u);
  EXPECT_EQ(b.stats().axis_fallbacks, 1);
  EXPECT_EQ(blobs[0].area, 31 * 5);
  EXPECT_FLOAT_EQ(blobs[0].u, 25.0f);
}

}  // namespace
}  // namespace ephor::vision
