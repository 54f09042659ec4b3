#include "common/shepherd/vision/threshold_selector.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "common/shepherd/vision/synthetic_image.h"

namespace ephor::vision {
namespace {

// Adds `n` pixels spread as a Gaussian of mean `mean`, sd `sd` grey levels.
void add_gaussian(Histogram& h, double mean, double sd, double n) {
  for (int g = 0; g < 256; ++g) {
    const double z = (g - mean) / sd;
    h[static_cast<size_t>(g)] += static_cast<uint32_t>(
        std::lround(n * std::exp(-0.5 * z * z) / (sd * std::sqrt(2.0 * M_PI))));
  }
}

TEST(ThresholdSelectorTest, BimodalHistogramThresholdIs85PercentTowardObjectPeak) {
  Histogram h{};
  add_gaussian(h, 40.0, 5.0, 240000.0);
  add_gaussian(h, 200.0, 4.0, 1500.0);
  const ThresholdChoice c = ThresholdSelector().select(h);
  ASSERT_EQ(c.status, ThresholdStatus::kOk) << c.message;
  EXPECT_EQ(c.background_peak, 40);
  EXPECT_EQ(c.object_peak, 200);
  EXPECT_EQ(c.threshold, 176);  // 40 + 0.85 * (200 - 40)
  EXPECT_GT(c.background_tail, 55);
  EXPECT_LE(c.background_tail, 70);
}

TEST(ThresholdSelectorTest, FractionIsConfigurable) {
  Histogram h{};
  add_gaussian(h, 40.0, 5.0, 240000.0);
  add_gaussian(h, 200.0, 4.0, 1500.0);
  ThresholdSelectorConfig cfg;
  cfg.fraction = 0.5;
  EXPECT_EQ(ThresholdSelector(cfg).select(h).threshold, 120);
}

TEST(ThresholdSelectorTest, TinyObjectPeakIsFound) {
  // 30 bright pixels in a quarter-million-pixel frame (one 6 px mark).
  Histogram h{};
  add_gaussian(h, 50.0, 6.0, 250000.0);
  h[220] += 30;
  const ThresholdChoice c = ThresholdSelector().select(h);
  ASSERT_EQ(c.status, ThresholdStatus::kOk) << c.message;
  EXPECT_EQ(c.object_peak, 220);
  EXPECT_EQ(c.threshold, 195);  // 50 + 0.85 * 170 = 194.5
}

TEST(ThresholdSelectorTest, NoObjectPeakIsAStatusWithAProvisionalThreshold) {
  Histogram h{};
  add_gaussian(h, 40.0, 5.0, 240000.0);
  const ThresholdChoice c = ThresholdSelector().select(h);
  EXPECT_EQ(c.status, ThresholdStatus::kNoObjectPeak);
  EXPECT_FALSE(c.message.empty());
  EXPECT_EQ(c.object_peak, -1);
  EXPECT_GT(c.threshold, c.background_tail);  // above every field pixel
  EXPECT_LE(c.threshold, 254);
}

TEST(ThresholdSelectorTest, FlatNoiseAboveTheFieldIsNotAnObjectPeak) {
  std::mt19937 rng(3);
  std::uniform_int_distribution<uint32_t> salt(0, 3);
  Histogram h{};
  add_gaussian(h, 40.0, 5.0, 240000.0);
  for (auto& n : h) n += salt(rng);
  EXPECT_EQ(ThresholdSelector().select(h).status, ThresholdStatus::kNoObjectPeak);
  // ... but a real peak in the same noise is still found.
  add_gaussian(h, 190.0, 4.0, 800.0);
  const ThresholdChoice c = ThresholdSelector().select(h);
  ASSERT_EQ(c.status, ThresholdStatus::kOk) << c.message;
  EXPECT_NEAR(c.object_peak, 190, 2);
}

TEST(ThresholdSelectorTest, EmptyHistogram) {
  const ThresholdChoice c = ThresholdSelector().select(Histogram{});
  EXPECT_EQ(c.status, ThresholdStatus::kEmptyHistogram);
  EXPECT_EQ(c.threshold, 128);
}

TEST(ThresholdSelectorTest, FromANoisyFrameWithSixMarks) {
  std::mt19937 rng(11);
  SyntheticImage img(512, 482, 40.0f);
  for (int i = 0; i < 6; ++i) img.add_disc(60.0 + 70.0 * i, 100.0 + 40.0 * i, 8.0, 200.0f);
  const ImageView view = img.render(4.0, rng);
  const Histogram h = ThresholdSelector::histogram(view);
  uint64_t total = 0;
  for (uint32_t n : h) total += n;
  EXPECT_EQ(total, 512u * 482u);
  const ThresholdChoice c = ThresholdSelector().select(view);
  ASSERT_EQ(c.status, ThresholdStatus::kOk) << c.message;
  EXPECT_NEAR(c.background_peak, 40, 1);
  EXPECT_NEAR(c.object_peak, 200, 2);
  EXPECT_NEAR(c.threshold, 176, 2);
}

TEST(ThresholdSelectorTest, UnevenLightingWidensTheFieldLobeOnly) {
  // The field brightens from grey 30 at the left to 70 at the right.
  std::mt19937 rng(13);
  SyntheticImage img(512, 482, 40.0f);
  for (int u = 0; u < 512; ++u) img.add_rect(u, 0, u, 481, 30.0f + 40.0f * u / 511.0f);
  for (int i = 0; i < 6; ++i) img.add_disc(60.0 + 70.0 * i, 100.0 + 40.0 * i, 8.0, 210.0f);
  const ThresholdChoice c = ThresholdSelector().select(img.render(4.0, rng));
  ASSERT_EQ(c.status, ThresholdStatus::kOk) << c.message;
  EXPECT_NEAR(c.object_peak, 210, 2);
  EXPECT_GT(c.threshold, 80);  // above the brightest field pixels
  EXPECT_LT(c.threshold, 210);
}

TEST(ThresholdSelectorTest, RejectsBadConfig) {
  ThresholdSelectorConfig c;
  c.fraction = 1.0;
  EXPECT_THROW(ThresholdSelector{c}, std::invalid_argument);
  c = {};
  c.min_object_pixels = 0;
  EXPECT_THROW(ThresholdSelector{c}, std::invalid_argument);
}

}  // namespace
}  // namespace ephor::vision
