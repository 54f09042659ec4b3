#include "common/shepherd/vision/vision_pipeline.h"

#include <random>

#include <gtest/gtest.h>

#include "common/shepherd/vision/synthetic_image.h"

namespace ephor::vision {
namespace {

class VisionPipelineTest : public ::testing::Test {
 protected:
  ImageView marks(std::initializer_list<std::pair<double, double>> centres) {
    img_.fill(40.0f);
    for (const auto& [u, v] : centres) img_.add_disc(u, v, 8.0, 200.0f);
    return img_.render(3.0, rng_);
  }
  SyntheticImage img_{256, 200, 40.0f};
  std::mt19937 rng_{5};
};

TEST_F(VisionPipelineTest, PicksThresholdOnFirstFrameThenKeepsIt) {
  VisionPipeline p;
  FrameResult r = p.process(marks({{60.0, 60.0}, {150.0, 120.0}}));
  ASSERT_EQ(r.status, FrameStatus::kOk);
  EXPECT_TRUE(r.threshold_picked);
  EXPECT_FALSE(r.threshold_provisional);
  EXPECT_NEAR(r.threshold, 176, 2);
  EXPECT_EQ(r.blobs->size(), 2u);
  r = p.process(marks({{61.0, 60.0}, {150.0, 121.0}}));
  EXPECT_FALSE(r.threshold_picked);
  EXPECT_EQ(r.blobs->size(), 2u);
}

TEST_F(VisionPipelineTest, EmptyFieldGivesProvisionalThresholdUntilMarksAppear) {
  VisionPipeline p;
  FrameResult r = p.process(marks({}));
  ASSERT_EQ(r.status, FrameStatus::kOk);
  EXPECT_TRUE(r.threshold_provisional);
  EXPECT_TRUE(r.blobs->empty());
  EXPECT_EQ(p.last_threshold_choice().status, ThresholdStatus::kNoObjectPeak);
  r = p.process(marks({{100.0, 100.0}}));
  EXPECT_TRUE(r.threshold_picked);
  EXPECT_FALSE(r.threshold_provisional);
  EXPECT_EQ(r.blobs->size(), 1u);
  EXPECT_NEAR(r.threshold, 176, 3);
}

TEST_F(VisionPipelineTest, PausedSearchesNothing) {
  VisionPipeline p;
  VisionSettings s;
  s.paused = true;
  ASSERT_EQ(p.apply(s), "");
  const FrameResult r = p.process(marks({{60.0, 60.0}}));
  EXPECT_EQ(r.status, FrameStatus::kPaused);
  EXPECT_TRUE(r.blobs->empty());
}

TEST_F(VisionPipelineTest, BadFrameIsAStatus) {
  VisionPipeline p;
  const FrameResult r = p.process(ImageView{nullptr, 512, 482, 512});
  EXPECT_EQ(r.status, FrameStatus::kBadFrame);
  EXPECT_NE(r.error.find("no pixel data"), std::string::npos);
  EXPECT_NE(r.blobs, nullptr);
}

TEST_F(VisionPipelineTest, InvalidSettingsAreRejectedAndOldOnesKept) {
  VisionPipeline p;
  VisionSettings s;
  s.threshold = 300;
  EXPECT_NE(p.apply(s).find("threshold 300"), std::string::npos);
  s.threshold = kThresholdAuto;
  s.mode = static_cast<SearchMode>(7);
  EXPECT_NE(p.apply(s).find("mode 7"), std::string::npos);
  EXPECT_EQ(p.settings().mode, SearchMode::kBlobify);
  EXPECT_EQ(p.settings().threshold, kThresholdAuto);
}

TEST_F(VisionPipelineTest, FixedThresholdAndRuntimeModeSwitch) {
  VisionPipeline p;
  VisionSettings s;
  s.threshold = 150;
  s.mode = SearchMode::kTrackify;
  ASSERT_EQ(p.apply(s), "");
  FrameResult r = p.process(marks({{60.0, 60.0}}));
  EXPECT_EQ(r.threshold, 150);
  EXPECT_FALSE(r.threshold_picked);
  EXPECT_EQ(r.mode, SearchMode::kTrackify);
  EXPECT_TRUE(r.full_search);  // trackify starts from a full search
  r = p.process(marks({{61.0, 60.0}}));
  EXPECT_FALSE(r.full_search);
  ASSERT_EQ(r.blobs->size(), 1u);
  EXPECT_NEAR((*r.blobs)[0].u, 61.0, 0.3);
  // Back to auto threshold: picked again on the next frame.
  s.threshold = kThresholdAuto;
  s.scan = ScanMode::kAxis;
  ASSERT_EQ(p.apply(s), "");
  r = p.process(marks({{62.0, 60.0}}));
  EXPECT_TRUE(r.threshold_picked);
  EXPECT_EQ(r.scan, ScanMode::kAxis);
  ASSERT_EQ(r.blobs->size(), 1u);
  // Repeating the same full-state command changes nothing.
  ASSERT_EQ(p.apply(s), "");
  r = p.process(marks({{63.0, 60.0}}));
  EXPECT_FALSE(r.threshold_picked);
  EXPECT_FALSE(r.full_search);
}

}  // namespace
}  // namespace ephor::vision
