#include "common/shepherd/sim/cloud_field.h"

#include <cmath>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "common/shepherd/sim/camera_renderer.h"

namespace ephor::sim {
namespace {

TEST(Cloud, OpaqueCoreSoftEdgeNothingOutside) {
  Cloud c;
  c.centre_px = {100.0, 100.0};
  c.semi_u_px = 50.0;
  c.semi_v_px = 25.0;
  c.opacity = 0.9;
  c.core = 0.5;
  EXPECT_DOUBLE_EQ(c.weight({100.0, 100.0}), 0.9);
  EXPECT_DOUBLE_EQ(c.weight({120.0, 100.0}), 0.9);  // r = 0.4, in the core
  EXPECT_DOUBLE_EQ(c.weight({100.0, 126.0}), 0.0);  // beyond the short semi-axis
  EXPECT_DOUBLE_EQ(c.weight({151.0, 100.0}), 0.0);
  // Halfway through the soft edge (r = 0.75): smoothstep(0.5) = 0.5.
  EXPECT_NEAR(c.weight({137.5, 100.0}), 0.45, 1e-12);
  // Monotone from the core to the edge.
  double last = 1.0;
  for (double u = 125.0; u <= 150.0; u += 1.0) {
    const double w = c.weight({u, 100.0});
    EXPECT_LE(w, last + 1e-12);
    last = w;
  }
}

TEST(CloudField, DriftsInStraightLinesAndWrapsRoundTheImage) {
  CloudFieldConfig config;
  config.clouds = 4;
  config.seed = 3;
  const CloudField field(config, 512, 482);
  ASSERT_EQ(field.size(), 4);
  const auto a = field.at(0.0), b = field.at(1.0), c = field.at(2.0);
  for (size_t i = 0; i < a.size(); ++i) {
    const Eigen::Vector2d v1 = b[i].centre_px - a[i].centre_px;
    const double speed = v1.norm();
    if (speed > 100.0) continue;  // wrapped in this second
    EXPECT_GE(speed, config.min_speed_px_s - 1e-9);
    EXPECT_LE(speed, config.max_speed_px_s + 1e-9);
  }
  // Alternately dark and bright, and always somewhere on or near the image.
  EXPECT_EQ(a[0].level, config.dark_level);
  EXPECT_EQ(a[1].level, config.bright_level);
  for (double t = 0.0; t < 600.0; t += 7.3) {
    for (const auto& cl : field.at(t)) {
      EXPECT_GE(cl.centre_px.x(), -config.max_semi_px - 1e-9);
      EXPECT_LE(cl.centre_px.x(), 512.0 + config.max_semi_px + 1e-9);
      EXPECT_GE(cl.centre_px.y(), -config.max_semi_px - 1e-9);
      EXPECT_LE(cl.centre_px.y(), 482.0 + config.max_semi_px + 1e-9);
    }
  }
  // Same seed, same clouds.
  const CloudField again(config, 512, 482);
  EXPECT_EQ(again.at(2.0)[3].centre_px, c[3].centre_px);
}

TEST(CloudField, BadConfigIsRefused) {
  CloudFieldConfig config;
  config.clouds = -1;
  EXPECT_THROW(CloudField(config, 512, 482), std::invalid_argument);
  config.clouds = 2;
  config.max_semi_px = 1.0;  // below min_semi_px
  EXPECT_THROW(CloudField(config, 512, 482), std::invalid_argument);
}

// A cloud's core over a mark hides it from the marks' threshold (paper 003,
// section 6: "frequently obscured sheep"); bright clouds stay below it.
TEST(CloudField, CoreHidesAMarkAndNoCloudPassesForOne) {
  CameraConfig cc;
  cc.noise_sigma = 0.0;
  WorldConfig wc;
  CameraRenderer r(cc, wc);
  SheepState s;
  s.id = 1;
  s.centre_mm = {400.0, 300.0};
  s.velocity_mm_s = {0.0, 0.0};
  std::vector<uint8_t> clear, clouded;
  const auto views = r.render({s}, {}, clear);
  const Eigen::Vector2d m = views[0].centre_px;
  const CloudFieldConfig defaults;
  for (const double level : {defaults.dark_level, defaults.bright_level}) {
    Cloud over;
    over.centre_px = m;
    over.level = level;
    Cloud elsewhere = over;
    elsewhere.centre_px = m + Eigen::Vector2d(150.0, 0.0);
    r.render({s}, {}, clouded, nullptr, {over, elsewhere});
    int bright_clear = 0, bright_clouded = 0;
    for (size_t i = 0; i < clear.size(); ++i) {
      bright_clear += clear[i] > 140;
      bright_clouded += clouded[i] > 140;
    }
    EXPECT_GT(bright_clear, 150) << "the mark is missing without clouds";
    EXPECT_EQ(bright_clouded, 0) << "level " << level << ": the mark shows through the core, "
                                 << "or the cloud itself passes the marks' threshold";
  }
}

}  // namespace
}  // namespace ephor::sim
