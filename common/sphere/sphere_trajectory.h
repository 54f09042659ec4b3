#pragma once
// The sphere's motion relative to the sensor (paper 002, section 3): a 16 cm
// diameter orbital sample canister moving at constant velocity during a
// half-second trial. Section 4's trials: the centre passes through (0, 0, Z)
// at t = 0.25 s, moving up, to the right and toward the sensor, at Table 1's
// x/y speed for the distance and 3.6 cm/s in z.

#include <Eigen/Core>

namespace ephor::sphere {

constexpr double kSphereRadiusM = 0.08;  // 16 cm diameter (section 1; u in appendix A)

struct SphereTrajectory {
  Eigen::Vector3d position_at_t0_m = Eigen::Vector3d(0, 0, 5);  // centre at time t0_s, sensor frame
  Eigen::Vector3d velocity_m_s = Eigen::Vector3d::Zero();
  double t0_s = 0.0;
  double radius_m = kSphereRadiusM;

  Eigen::Vector3d centre_at(double t_s) const {
    return position_at_t0_m + velocity_m_s * (t_s - t0_s);
  }

  // Section 4's trial: through (0, 0, distance) at t_pass_s, up/right/toward.
  static SphereTrajectory paper_trial(double distance_m, double t_pass_s = 0.25);
};

// Table 1's "Total X" / "Total Y" speed (m/s) for a distance: 0.6 cm/s per
// 1 m of range (6 mrad/s about x or y) + 0.6 cm/s (6 mrad/s about z, 1 m
// lever arm) + 1.5 cm/s translation. Table 1's 2 m row prints 4.1 cm/s, but
// its own columns sum to 1.2 + 0.6 + 1.5 = 3.3 cm/s, and Table 2's 2 m row
// (2.65 deg) is what 3.3 cm/s gives (4.1 would give 2.72 deg): we use 3.3.
double table1_xy_speed_m_s(double distance_m);

constexpr double kTable1ZSpeedMS = 0.036;  // 3.0 cm/s translation + 0.6 cm/s from rotation about y
}  // namespace ephor::sphere
