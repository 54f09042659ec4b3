#include "common/shepherd/sim/camera_renderer.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

namespace ephor::sim {
namespace {

SheepState sheep_at(int32_t id, double x, double y, double angle) {
  SheepState s;
  s.id = id;
  s.centre_mm = {x, y};
  s.body_angle_rad = angle;
  s.velocity_mm_s = {0.0, 0.0};
  return s;
}

// Intensity-weighted centroid of the pixels above `floor` in a window around `near`.
Eigen::Vector2d weighted_centroid(const std::vector<uint8_t>& img, int w,
                                  const Eigen::Vector2d& near, double floor, int half = 14) {
  double sw = 0, su = 0, sv = 0;
  const int cu = static_cast<int>(std::lround(near.x())),
            cv = static_cast<int>(std::lround(near.y()));
  for (int v = cv - half; v <= cv + half; ++v) {
    for (int u = cu - half; u <= cu + half; ++u) {
      const double g =
          img[static_cast<size_t>(v) * static_cast<size_t>(w) + static_cast<size_t>(u)];
      const double wt = std::max(0.0, g - floor);
      sw += wt, su += wt * u, sv += wt * v;
    }
  }
  return {su / sw, sv / sw};
}

uint8_t pixel(const std::vector<uint8_t>& img, int w, const Eigen::Vector2d& p) {
  return img[static_cast<size_t>(std::lround(p.y())) * static_cast<size_t>(w) +
             static_cast<size_t>(std::lround(p.x()))];
}

TEST(CameraRenderer, FrameHasTheCameraSizeAndTheDocumentedLevels) {
  CameraConfig cc;
  WorldConfig wc;
  CameraRenderer r(cc, wc);
  std::vector<uint8_t> img;
  const auto views = r.render({sheep_at(1, 300, 300, 0.4)}, {}, img);
  ASSERT_EQ(img.size(), 512u * 482u);
  ASSERT_EQ(views.size(), 1u);
  // Field darker than the body, surroundings darker than the field, mark bright.
  const auto& cam = cc.camera;
  const uint8_t field = pixel(img, 512, cam.project(900, 700, 0));
  const uint8_t outside = pixel(img, 512, {3.0, 3.0});
  const uint8_t body =
      pixel(img, 512, cam.project(300 + 80 * std::cos(0.4), 300 + 80 * std::sin(0.4), 50));
  const uint8_t mark = pixel(img, 512, views[0].centre_px);
  std::vector<uint8_t> with_arm;
  const std::vector<ArmPart> arm = {{{900.0, 700.0, 100.0}, {900.0, 700.0, 300.0}, 40.0}};
  r.render({sheep_at(1, 300, 300, 0.4)}, arm, with_arm);
  EXPECT_LT(pixel(with_arm, 512, cam.project(900, 700, 300)) + 6, field) << "arm not dark";
  EXPECT_LT(outside, field);
  EXPECT_LT(field + 6, body);
  EXPECT_GT(mark, 200);
  // The mark is about 16 px across.
  EXPECT_NEAR(2.0 * views[0].radius_px, 15.6, 0.5);
}

// An arm link covers the capsule's area in the image at every angle: near
// horizontal (where its band is as wide as its bounding box) as well as steep
// or diagonal (where only a band of each row is drawn).
TEST(CameraRenderer, ArmLinkCoversItsCapsuleAtEveryAngle) {
  CameraConfig cc;
  cc.noise_sigma = 0.0;
  WorldConfig wc;
  CameraRenderer r(cc, wc);
  const auto& cam = cc.camera;
  const double z = 300.0, radius_mm = 30.0, length_mm = 300.0;
  const double r_px = radius_mm * cam.px_per_mm(z), l_px = length_mm * cam.px_per_mm(z);
  const double expected = std::numbers::pi * r_px * r_px + 2.0 * r_px * l_px;
  for (const double deg : {0.0, 0.5, 10.0, 30.0, 45.0, 60.0, 89.5, 90.0, 135.0}) {
    const double a = deg * std::numbers::pi / 180.0;
    const Eigen::Vector3d mid(609.0, 457.0, z);
    const Eigen::Vector3d half(0.5 * length_mm * std::cos(a), 0.5 * length_mm * std::sin(a), 0.0);
    std::vector<uint8_t> bare, img;
    r.render({}, {}, bare);
    r.render({}, {{mid - half, mid + half, radius_mm}}, img);
    // Arm 28 and field 40 grey levels (lighting within +-10 %): dark below 34,
    // as are the surroundings off the table (hence the frame without the arm).
    auto dark = [](const std::vector<uint8_t>& im) {
      return static_cast<double>(
          std::count_if(im.begin(), im.end(), [](uint8_t g) { return g < 34; }));
    };
    EXPECT_NEAR(dark(img) - dark(bare), expected, 0.03 * expected) << deg << " deg";
  }
}

TEST(CameraRenderer, MarkCentroidsMatchTheProjectedTruth) {
  CameraConfig cc;
  cc.noise_sigma = 0.0;  // lighting gradient and vignette stay on
  WorldConfig wc;
  CameraRenderer r(cc, wc);
  std::vector<SheepState> herd;
  int id = 1;
  // Sub-pixel offsets all over the field, bodies at several angles.
  for (double x = 150.3; x < 1100.0; x += 237.7)
    for (double y = 140.6; y < 800.0; y += 211.3) {
      herd.push_back(sheep_at(id, x, y, 0.37 * id));
      ++id;
    }
  std::vector<uint8_t> img;
  const auto views = r.render(herd, {}, img);
  double worst = 0.0;
  for (const auto& v : views) {
    // Weights above the body's level so only the mark counts.
    const Eigen::Vector2d c = weighted_centroid(img, 512, v.centre_px, 100.0);
    worst = std::max(worst, (c - v.centre_px).norm());
    EXPECT_TRUE(v.visible);
  }
  EXPECT_LT(worst, 0.1) << "worst centroid error " << worst << " px";
}

TEST(CameraRenderer, ThresholdSeparatesMarksFromEverythingElseUnderNoise) {
  CameraConfig cc;  // default noise and lighting
  WorldConfig wc;
  CameraRenderer r(cc, wc);
  const std::vector<SheepState> herd = {sheep_at(1, 100, 100, 0.0), sheep_at(2, 1120, 820, 1.0),
                                        sheep_at(3, 1120, 100, 2.0), sheep_at(4, 100, 820, -1.0)};
  // An arm part crossing the field, not over any mark.
  const std::vector<ArmPart> arm = {{{609.5, 457.0, 450.0}, {900.0, 457.0, 300.0}, 50.0}};
  std::vector<uint8_t> img;
  const auto views = r.render(herd, arm, img);
  // Only the marks' antialiased rims lie between the dark lobe (surroundings,
  // arm, field, bodies) and the marks: nothing else can pass for an object peak.
  int between = 0;
  for (const uint8_t g : img) between += (g > 70 && g < 200) ? 1 : 0;
  EXPECT_LT(between, 100 * static_cast<int>(views.size()));
  // Every pixel fully inside a mark is above 200; everything away from marks is below 150.
  for (int v = 0; v < 482; ++v) {
    for (int u = 0; u < 512; ++u) {
      double nearest = 1e9;
      double radius = 0.0;
      for (const auto& mv : views) {
        const double d = (Eigen::Vector2d(u, v) - mv.centre_px).norm();
        if (d < nearest) nearest = d, radius = mv.radius_px;
      }
      const uint8_t g = img[static_cast<size_t>(v) * 512 + static_cast<size_t>(u)];
      if (nearest < radius - 1.0) {
        ASSERT_GT(g, 200) << "mark pixel (" << u << ", " << v << ")";
      } else if (nearest > radius + 1.0) {
        ASSERT_LT(g, 150) << "non-mark pixel (" << u << ", " << v << ")";
      }
    }
  }
}

TEST(CameraRenderer, ArmOverASheepHidesItInTruthAndInTheImage) {
  CameraConfig cc;
  WorldConfig wc;
  CameraRenderer r(cc, wc);
  const std::vector<SheepState> herd = {sheep_at(1, 400, 300, 0.0), sheep_at(2, 800, 600, 0.0)};
  // A wrist-sized part hanging over sheep 1.
  const std::vector<ArmPart> arm = {{{400.0, 300.0, 130.0}, {420.0, 300.0, 300.0}, 40.0}};
  std::vector<uint8_t> img;
  const auto views = r.render(herd, arm, img);
  ASSERT_EQ(views.size(), 2u);
  EXPECT_FALSE(views[0].visible);
  EXPECT_GT(views[0].hidden_fraction, 0.99);
  EXPECT_TRUE(views[1].visible);
  EXPECT_EQ(views[1].hidden_fraction, 0.0);
  int bright_near_1 = 0, bright_near_2 = 0;
  for (int v = 0; v < 482; ++v) {
    for (int u = 0; u < 512; ++u) {
      if (img[static_cast<size_t>(v) * 512 + static_cast<size_t>(u)] <= 180) continue;
      if ((Eigen::Vector2d(u, v) - views[0].centre_px).norm() < 20.0) ++bright_near_1;
      if ((Eigen::Vector2d(u, v) - views[1].centre_px).norm() < 20.0) ++bright_near_2;
    }
  }
  EXPECT_EQ(bright_near_1, 0) << "hidden mark still shows";
  EXPECT_GT(bright_near_2, 150) << "visible mark missing";
  // Half hidden: a thin part across the mark's edge leaves it visible.
  const std::vector<ArmPart> thin = {{{400.0, 330.0, 100.0}, {400.0, 600.0, 100.0}, 10.0}};
  EXPECT_TRUE(r.mark_views(herd, thin)[0].visible);
}

TEST(CameraRenderer, SameSeedSameNoise) {
  CameraConfig cc;
  WorldConfig wc;
  CameraRenderer a(cc, wc), b(cc, wc);
  cc.seed = 2;
  CameraRenderer c(cc, wc);
  std::vector<uint8_t> ia, ib, ic;
  const std::vector<SheepState> herd = {sheep_at(1, 400, 300, 0.0)};
  for (int i = 0; i < 3; ++i) {
    a.render(herd, {}, ia);
    b.render(herd, {}, ib);
    c.render(herd, {}, ic);
    EXPECT_EQ(ia, ib);
    EXPECT_NE(ia, ic);
  }
}

TEST(CameraRenderer, BadConfigIsRefused) {
  CameraConfig cc;
  cc.noise_sigma = -1.0;
  EXPECT_THROW(CameraRenderer(cc, WorldConfig{}), std::invalid_argument);
  cc = CameraConfig{};
  cc.mark_level = 300.0;
  EXPECT_THROW(CameraRenderer(cc, WorldConfig{}), std::invalid_argument);
}

}  // namespace
}  // namespace ephor::sim
