#include "common/camera/channel_converter.h"

#include <stdexcept>

#include <gtest/gtest.h>

namespace ephor::camera {
namespace {

TEST(ChannelConverterTest, PicksTheConfiguredColourChannel) {
  // B = 10, G = 200, R = 90 everywhere, one pixel different.
  cv::Mat bgr(4, 6, CV_8UC3, cv::Scalar(10, 200, 90));
  bgr.at<cv::Vec3b>(2, 5) = cv::Vec3b(1, 2, 3);
  std::vector<uint8_t> out;
  ChannelConverter green;
  green.convert(bgr, out);
  ASSERT_EQ(out.size(), 24u);
  EXPECT_EQ(out[0], 200);
  EXPECT_EQ(out[2 * 6 + 5], 2);  // row-major, row 2 column 5
  ChannelConverter(ColourChannel::kRed).convert(bgr, out);
  EXPECT_EQ(out[0], 90);
  ChannelConverter(ColourChannel::kBlue).convert(bgr, out);
  EXPECT_EQ(out[0], 10);
  ChannelConverter(ColourChannel::kGrey).convert(bgr, out);
  EXPECT_NEAR(out[0], 0.299 * 90 + 0.587 * 200 + 0.114 * 10, 1.0);
}

TEST(ChannelConverterTest, GreyBgraAnd16BitImages) {
  std::vector<uint8_t> out;
  ChannelConverter green;
  green.convert(cv::Mat(3, 3, CV_8UC1, cv::Scalar(77)), out);
  EXPECT_EQ(out[4], 77);
  green.convert(cv::Mat(3, 3, CV_8UC4, cv::Scalar(1, 150, 3, 255)), out);
  EXPECT_EQ(out[4], 150);
  green.convert(cv::Mat(3, 3, CV_16UC3, cv::Scalar(0, 257 * 100, 0)), out);
  EXPECT_EQ(out[4], 100);
}

TEST(ChannelConverterTest, UnsupportedImagesAreNamed) {
  std::vector<uint8_t> out;
  ChannelConverter green;
  EXPECT_THROW(green.convert(cv::Mat(), out), std::invalid_argument);
  EXPECT_THROW(green.convert(cv::Mat(2, 2, CV_32FC3), out), std::invalid_argument);
  try {
    green.convert(cv::Mat(2, 2, CV_8UC2), out);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("2 channels"), std::string::npos) << e.what();
  }
  EXPECT_EQ(parse_colour_channel("grey"), ColourChannel::kGrey);
  EXPECT_THROW(parse_colour_channel("purple"), std::invalid_argument);
}

}  // namespace
}  // namespace ephor::camera
