#include "common/shepherd/calibrate/tool_spot_finder.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

namespace ephor::calibrate {
namespace {

// A dark, unevenly lit frame with Gaussian noise (fixed seed).
GreyFrame background(uint64_t seed) {
  GreyFrame f{512, 482, std::vector<uint8_t>(512 * 482)};
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, 2.5);
  for (int v = 0; v < f.height; ++v)
    for (int u = 0; u < f.width; ++u)
      f.data[static_cast<size_t>(v * f.width + u)] =
          static_cast<uint8_t>(std::lround(std::clamp(40.0 + 0.02 * u + noise(rng), 0.0, 255.0)));
  return f;
}

// Adds an antialiased bright disc (16 x 16 subsamples per pixel).
void disc(GreyFrame& f, Eigen::Vector2d c, double r, double level) {
  for (int v = static_cast<int>(c.y() - r - 2); v <= static_cast<int>(c.y() + r + 2); ++v)
    for (int u = static_cast<int>(c.x() - r - 2); u <= static_cast<int>(c.x() + r + 2); ++u) {
      int in = 0;
      for (int a = 0; a < 16; ++a)
        for (int b = 0; b < 16; ++b)
          in += std::hypot(u - 0.5 + (a + 0.5) / 16 - c.x(), v - 0.5 + (b + 0.5) / 16 - c.y()) < r;
      auto& p = f.data[static_cast<size_t>(v * f.width + u)];
      p = static_cast<uint8_t>(std::lround(p + (level - p) * in / 256.0));
    }
}

TEST(ToolSpotFinder, FindsTheLightToATenthOfAPixel) {
  ToolSpotFinder finder;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> pos(30.0, 450.0);
  for (int i = 0; i < 20; ++i) {
    const Eigen::Vector2d c(pos(rng), pos(rng));
    GreyFrame dark = background(100 + i);
    GreyFrame lit = background(200 + i);  // fresh noise, as a second camera frame
    disc(lit, c, 6.0, 250.0);
    const auto r = finder.find(lit, dark);
    ASSERT_TRUE(r.spot) << r.reason;
    EXPECT_LT((r.spot->centre_px - c).norm(), 0.1) << "at " << c.transpose();
    EXPECT_NEAR(r.spot->area_px, M_PI * 36.0, 20.0);
  }
}

TEST(ToolSpotFinder, IgnoresMarksStillOrWalking) {
  GreyFrame dark = background(1), lit = background(2);
  for (auto* f : {&dark, &lit}) {  // sheep marks as bright as the light, standing
    disc(*f, {100.0, 100.0}, 8.0, 240.0);
    disc(*f, {300.0, 200.0}, 8.0, 240.0);
  }
  disc(dark, {200.0, 400.0}, 8.0, 240.0);  // a walking sheep's mark, 1.5 px on in the lit frame
  disc(lit, {201.5, 400.0}, 8.0, 240.0);
  disc(lit, {310.0, 215.0}, 6.0, 250.0);  // the light right beside a mark
  const auto r = ToolSpotFinder().find(lit, dark);
  ASSERT_TRUE(r.spot) << r.reason;
  EXPECT_LT((r.spot->centre_px - Eigen::Vector2d(310.0, 215.0)).norm(), 0.3);
}

TEST(ToolSpotFinder, RejectsAmbiguousAndMissingSpotsWithAReason) {
  ToolSpotFinder finder;
  GreyFrame dark = background(3), lit = background(4);
  auto none = finder.find(lit, dark);
  EXPECT_FALSE(none.spot);
  EXPECT_NE(none.reason.find("no light spot"), std::string::npos) << none.reason;

  disc(lit, {100.0, 100.0}, 6.0, 250.0);
  disc(lit, {400.0, 300.0}, 6.0, 250.0);  // e.g. a sheep's mark moved between the frames
  auto two = finder.find(lit, dark);
  EXPECT_FALSE(two.spot);
  EXPECT_NE(two.reason.find("ambiguous: 2"), std::string::npos) << two.reason;

  // The expected position picks one of them; a far-off expectation finds none.
  auto gated = finder.find(lit, dark, Eigen::Vector2d(395.0, 305.0));
  ASSERT_TRUE(gated.spot) << gated.reason;
  EXPECT_LT((gated.spot->centre_px - Eigen::Vector2d(400.0, 300.0)).norm(), 0.2);
  auto far = finder.find(lit, dark, Eigen::Vector2d(250.0, 250.0));
  EXPECT_FALSE(far.spot);
  EXPECT_NE(far.reason.find("outside the gate"), std::string::npos) << far.reason;
}

TEST(ToolSpotFinder, RejectsLargeChangesAndMismatchedFrames) {
  ToolSpotFinder finder;
  GreyFrame dark = background(5), lit = background(6);
  disc(lit, {200.0, 200.0}, 30.0, 250.0);  // the lighting changed, or the arm moved
  auto big = finder.find(lit, dark);
  EXPECT_FALSE(big.spot);
  EXPECT_NE(big.reason.find("1 too large"), std::string::npos) << big.reason;

  GreyFrame small{10, 10, std::vector<uint8_t>(100)};
  EXPECT_FALSE(finder.find(lit, small).spot);
  GreyFrame broken{512, 482, {}};
  EXPECT_FALSE(finder.find(broken, dark).spot);
  EXPECT_THROW(ToolSpotFinder(ToolSpotFinderConfig{.min_contrast = NAN}), std::invalid_argument);
}

}  // namespace
}  // namespace ephor::calibrate
