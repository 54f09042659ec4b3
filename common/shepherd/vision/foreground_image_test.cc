#include "common/shepherd/vision/foreground_image.h"

#include <stdexcept>

#include <gtest/gtest.h>

#include "common/shepherd/vision/blobifier.h"
#include "common/shepherd/vision/synthetic_image.h"
#include "common/shepherd/vision/vision_pipeline.h"

namespace ephor::vision {
namespace {

// A grey-200 floor with a dark 12 x 12 px square whose top-left corner is at (u, v).
ImageView dark_square(SyntheticImage& img, int u, int v) {
  img.fill(200.0f);
  img.add_rect(u, v, u + 11, v + 11, 30.0f);
  return img.render();
}

TEST(ForegroundImageTest, BrightIsTheFrameItself) {
  SyntheticImage img(64, 48, 10.0f);
  const ImageView frame = img.render();
  ForegroundImage fg;
  const ImageView out = fg.apply(frame);
  EXPECT_EQ(out.data, frame.data);
}

TEST(ForegroundImageTest, DarkObjectsBecomeBrightBlobs) {
  SyntheticImage img(100, 80, 200.0f);
  ForegroundImage fg({ForegroundMode::kDark, 1.0, 0});
  const ImageView out = fg.apply(dark_square(img, 40, 30));
  EXPECT_EQ(out.at(45, 35), 255 - 30);
  EXPECT_EQ(out.at(5, 5), 255 - 200);
  Blobifier blobifier;
  const auto& blobs = blobifier.blobify(out, 128, ScanMode::kFull);
  ASSERT_EQ(blobs.size(), 1u);
  EXPECT_FLOAT_EQ(blobs[0].u, 45.5f);
  EXPECT_FLOAT_EQ(blobs[0].v, 35.5f);
  EXPECT_EQ(blobs[0].area, 144);
}

TEST(ForegroundImageTest, MotionLightsUpWhatMovedAndNotTheStillBackground) {
  SyntheticImage img(100, 80, 200.0f);
  ForegroundImage fg({ForegroundMode::kMotion, 1.0, 0});
  // First frame: no reference yet, nothing moves.
  ImageView out = fg.apply(dark_square(img, 20, 30));
  for (int v = 0; v < 80; ++v)
    for (int u = 0; u < 100; ++u) ASSERT_EQ(out.at(u, v), 0) << u << "," << v;
  // Same frame again: still nothing.
  out = fg.apply(dark_square(img, 20, 30));
  EXPECT_EQ(out.at(25, 35), 0);
  // Moved 30 px right: both where it was and where it is now light up
  // (frame differencing against the previous frame).
  out = fg.apply(dark_square(img, 50, 30));
  EXPECT_EQ(out.at(25, 35), 170);
  EXPECT_EQ(out.at(55, 35), 170);
  EXPECT_EQ(out.at(5, 5), 0);
  Blobifier blobifier;
  EXPECT_EQ(blobifier.blobify(out, 50, ScanMode::kFull).size(), 2u);
}

TEST(ForegroundImageTest, RunningAverageReferenceForgetsWhereTheObjectWasSlowly) {
  SyntheticImage img(100, 80, 200.0f);
  ForegroundImage fg({ForegroundMode::kMotion, 0.1, 0});
  for (int i = 0; i < 3; ++i) fg.apply(dark_square(img, 70, 60));
  // An empty floor learnt for many frames, then the object appears.
  img.fill(200.0f);
  ForegroundImage empty_floor({ForegroundMode::kMotion, 0.1, 0});
  for (int i = 0; i < 50; ++i) empty_floor.apply(img.render());
  const ImageView out = empty_floor.apply(dark_square(img, 40, 30));
  EXPECT_EQ(out.at(45, 35), 170);
  EXPECT_EQ(out.at(5, 5), 0);
  // The reference moved a tenth of the way to the object: 17 grey levels.
  const ImageView next = empty_floor.apply(dark_square(img, 40, 30));
  EXPECT_EQ(next.at(45, 35), 153);
}

TEST(ForegroundImageTest, SmoothingJoinsTheTwoEdgesOfAMovingBar) {
  // A uniform bar moving 3 px: frame differencing sees only two 3 px wide
  // strips (leading and trailing edge); a 4 px box filter joins them.
  SyntheticImage img(100, 80, 200.0f);
  const auto bar = [&img](int u) {
    img.fill(200.0f);
    img.add_rect(u, 20, u + 9, 59, 20.0f);
    return img.render();
  };
  Blobifier blobifier({1, 10, 256, 1.5f});
  ForegroundImage raw({ForegroundMode::kMotion, 1.0, 0});
  raw.apply(bar(30));
  EXPECT_EQ(blobifier.blobify(raw.apply(bar(33)), 30, ScanMode::kFull).size(), 2u);
  ForegroundImage smoothed({ForegroundMode::kMotion, 1.0, 4});
  smoothed.apply(bar(30));
  const auto& blobs = blobifier.blobify(smoothed.apply(bar(33)), 30, ScanMode::kFull);
  ASSERT_EQ(blobs.size(), 1u);
  EXPECT_NEAR(blobs[0].u, 36.0, 1.0);  // the middle of the old and new bar
  EXPECT_NEAR(blobs[0].v, 39.5, 0.5);
}

TEST(ForegroundImageTest, SizeChangeRestartsTheReference) {
  SyntheticImage small(50, 40, 100.0f), large(60, 40, 180.0f);
  ForegroundImage fg({ForegroundMode::kMotion, 1.0, 0});
  fg.apply(small.render());
  const ImageView out = fg.apply(large.render());
  EXPECT_EQ(out.width, 60);
  EXPECT_EQ(out.at(10, 10), 0);
}

TEST(ForegroundImageTest, BadConfigAndImagesAreNamed) {
  EXPECT_THROW(ForegroundImage({ForegroundMode::kMotion, 0.0, 0}), std::invalid_argument);
  EXPECT_THROW(ForegroundImage({ForegroundMode::kMotion, 1.5, 0}), std::invalid_argument);
  EXPECT_THROW(ForegroundImage({ForegroundMode::kMotion, 1.0, -1}), std::invalid_argument);
  EXPECT_EQ(parse_foreground_mode("dark"), ForegroundMode::kDark);
  try {
    parse_foreground_mode("green");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'green'"), std::string::npos);
  }
  ForegroundImage fg({ForegroundMode::kDark, 1.0, 0});
  EXPECT_THROW(fg.apply(ImageView{nullptr, 10, 10, 10}), std::invalid_argument);
}

TEST(ForegroundImageTest, PipelineFindsDarkObjectsWithTheAutoThreshold) {
  SyntheticImage img(256, 200, 200.0f);
  img.add_disc(60.0, 70.0, 8.0, 30.0f);
  img.add_disc(180.0, 120.0, 8.0, 30.0f);
  std::mt19937 rng(3);
  PipelineConfig cfg;
  cfg.foreground.mode = ForegroundMode::kDark;
  VisionPipeline pipeline(cfg);
  const FrameResult r = pipeline.process(img.render(3.0, rng));
  ASSERT_EQ(r.status, FrameStatus::kOk);
  ASSERT_EQ(r.blobs->size(), 2u);
  EXPECT_NEAR((*r.blobs)[0].u, 60.0, 0.3);
  EXPECT_NEAR((*r.blobs)[0].v, 70.0, 0.3);
  // The bright (default) pipeline finds nothing dark.
  VisionPipeline bright;
  EXPECT_TRUE(bright.process(img.render(3.0, rng)).blobs->empty());
}

}  // namespace
}  // namespace ephor::vision
