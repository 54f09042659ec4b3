#pragma once
// A rigid pose as our LCM messages carry it: a rotation as 9 doubles,
// row-major (p_out = R p_in + t), and a translation as 3 (mm). Written once
// for every system's messages (board to camera, target in base, flange in
// table, ...).

#include <Eigen/Geometry>

namespace ephor::geometry {

inline Eigen::Isometry3d pose_of(const double r[9], const double t[3]) {
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) p.linear()(i, j) = r[3 * i + j];
    p.translation()[i] = t[i];
  }
  return p;
}

inline void set_pose(const Eigen::Isometry3d& pose, double r[9], double t[3]) {
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) r[3 * i + j] = pose.linear()(i, j);
    t[i] = pose.translation()[i];
  }
}

}  // namespace ephor::geometry
