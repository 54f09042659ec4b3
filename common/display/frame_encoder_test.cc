#include "common/display/frame_encoder.h"

#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

namespace ephor::display {
namespace {

TEST(FrameEncoderTest, JpegDecodesToTheSameImage) {
  const int w = 64, h = 48;
  std::vector<uint8_t> px(static_cast<size_t>(w * h), 40);
  for (int v = 10; v < 20; ++v)
    for (int u = 10; u < 30; ++u) px[static_cast<size_t>(v * w + u)] = 220;
  FrameEncoder enc(90);
  const auto& jpeg = enc.encode(px.data(), w * h, w, h);
  ASSERT_GT(jpeg.size(), 4u);
  EXPECT_EQ(jpeg[0], 0xFF);
  EXPECT_EQ(jpeg[1], 0xD8);
  const cv::Mat back = cv::imdecode(jpeg, cv::IMREAD_GRAYSCALE);
  ASSERT_EQ(back.cols, w);
  ASSERT_EQ(back.rows, h);
  EXPECT_NEAR(back.at<uint8_t>(15, 20), 220, 8);
  EXPECT_NEAR(back.at<uint8_t>(40, 50), 40, 8);
}

TEST(FrameEncoderTest, BadSizesAreRefused) {
  std::vector<uint8_t> px(100);
  FrameEncoder enc;
  EXPECT_THROW(enc.encode(px.data(), 100, 10, 11), std::invalid_argument);
  EXPECT_THROW(enc.encode(px.data(), 100, 0, 100), std::invalid_argument);
  EXPECT_THROW(FrameEncoder(0), std::invalid_argument);
}

}  // namespace
}  // namespace ephor::display
