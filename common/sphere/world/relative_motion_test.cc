#include "common/sphere/world/relative_motion.h"

#include <gtest/gtest.h>

namespace ephor::sphere {
namespace {

TEST(RelativeMotion, Table1DriftAtTwentyMetres) {
  const Eigen::Vector3d d = RelativeMotionConfig::table1_drift(20.0);
  EXPECT_NEAR(d.x(), 0.141, 1e-12);  // Table 1: 12.0 + 0.6 + 1.5 cm/s
  EXPECT_NEAR(d.y(), 0.141, 1e-12);
  EXPECT_NEAR(d.z(), -0.036, 1e-12);  // section 3: 3.0 + 0.6 cm/s toward the sensor
}

TEST(RelativeMotion, SphereDriftsAndChaserBurnsAtMostTheLimitPerWindow) {
  RelativeMotionConfig c;
  c.start_position_m = {0.1, 0.0, 10.0};
  c.target_velocity_m_s = {0.02, 0.0, -0.03};
  RelativeMotion m(c);
  // Window 0: no command change (chaser at rest).
  m.begin_window(0.0, Eigen::Vector3d::Zero());
  EXPECT_TRUE(m.position_at(0.5).isApprox(Eigen::Vector3d(0.11, 0.0, 9.985), 1e-12));
  // Window 1: chaser asked for 0.1 m/s along z; gets 0.05 * 0.5 = 0.025 m/s.
  const SphereTrajectory t = m.begin_window(0.5, Eigen::Vector3d(0, 0, 0.1));
  EXPECT_NEAR(m.chaser_velocity().z(), 0.025, 1e-12);
  EXPECT_NEAR(t.velocity_m_s.z(), -0.055, 1e-12);
  EXPECT_NEAR(m.position_at(1.0).z(), 9.985 - 0.0275, 1e-12);
  // A change within the limit is taken whole; the limit is on the vector.
  m.begin_window(1.0, Eigen::Vector3d(0.0, 0.01, 0.025));
  EXPECT_TRUE(m.chaser_velocity().isApprox(Eigen::Vector3d(0, 0.01, 0.025), 1e-12));
  m.begin_window(1.5, Eigen::Vector3d(0.3, 0.01, 0.025));
  EXPECT_NEAR(m.chaser_velocity().x(), 0.025, 1e-12);
  // Windows only go forward.
  EXPECT_THROW(m.begin_window(1.0, Eigen::Vector3d::Zero()), std::invalid_argument);
}

TEST(RelativeMotion, RefusesNonFiniteSettings) {
  RelativeMotionConfig c;
  c.target_velocity_m_s.x() = std::nan("");
  EXPECT_THROW(RelativeMotion{c}, std::invalid_argument);
  c = {};
  c.max_accel_m_s2 = -1;
  EXPECT_THROW(RelativeMotion{c}, std::invalid_argument);
}

}  // namespace
}  // namespace ephor::sphere
