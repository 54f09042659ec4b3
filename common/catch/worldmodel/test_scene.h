#pragma once
// Test and benchmark helpers for common/catch/worldmodel: a camera looking at
// the default board, and a simulated ball rolling down it.

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "common/catch/board_model.h"

namespace ephor::catching::testing {

// A camera 1500 mm in front of the board face, off the board's centre by
// (200, 300) mm in B, looking at the centre with image v roughly down the
// slope. Returns p_C = R p_B + t.
inline Pose camera_looking_at_board(const BoardSpec& board) {
  const Eigen::Vector3d target(0.5 * board.width_mm, 0.5 * board.height_mm, 0.0);
  const Eigen::Vector3d cam = target + Eigen::Vector3d(200.0, 300.0, 1500.0);
  const Eigen::Vector3d z = (target - cam).normalized();
  const Eigen::Vector3d y =
      (Eigen::Vector3d::UnitY() - Eigen::Vector3d::UnitY().dot(z) * z).normalized();
  const Eigen::Vector3d x = y.cross(z);
  Eigen::Matrix3d r_bc;  // camera axes in B
  r_bc.col(0) = x;
  r_bc.col(1) = y;
  r_bc.col(2) = z;
  Pose board_to_camera = Pose::Identity();
  board_to_camera.linear() = r_bc.transpose();
  board_to_camera.translation() = -r_bc.transpose() * cam;
  return board_to_camera;
}

inline double rolling_acceleration(const BoardPlacement& placement) {
  return 5.0 / 7.0 * kGravityMmS2 * std::sin(placement.incline_rad);
}

struct RollingSample {
  double t_s = 0.0;
  Eigen::Vector2d position_mm = Eigen::Vector2d::Zero();  // true, B
  Eigen::Vector2d velocity_mm_s = Eigen::Vector2d::Zero();
  Eigen::Vector2d measured_mm = Eigen::Vector2d::Zero();  // with noise
};

// A peg bounce: at time t_s the velocity becomes `velocity_mm_s`.
struct Bounce {
  double t_s = 0.0;
  Eigen::Vector2d velocity_mm_s = Eigen::Vector2d::Zero();
};

// Samples every `period_s` from t = 0 until the centre passes y = height,
// integrating exactly between bounces. Noise is Gaussian, `noise_mm` per axis.
inline std::vector<RollingSample> simulate_roll(const BoardSpec& board, double accel_mm_s2,
                                                Eigen::Vector2d p0, Eigen::Vector2d v0,
                                                double period_s, double noise_mm, unsigned seed,
                                                std::vector<Bounce> bounces = {}) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, noise_mm);
  std::vector<RollingSample> out;
  Eigen::Vector2d p = p0, v = v0;
  double t = 0.0;
  std::size_t next_bounce = 0;
  const double fine = 1e-4;  // s, exact between steps for a piecewise constant acceleration
  for (int k = 0;; ++k) {
    const double t_k = k * period_s;
    while (t < t_k - 1e-12) {
      double step = std::min(fine, t_k - t);
      if (next_bounce < bounces.size() && bounces[next_bounce].t_s < t + step) {
        step = std::max(0.0, bounces[next_bounce].t_s - t);
        p += v * step + Eigen::Vector2d(0.0, 0.5 * accel_mm_s2 * step * step);
        v.y() += accel_mm_s2 * step;
        t += step;
        v = bounces[next_bounce].velocity_mm_s;
        ++next_bounce;
        continue;
      }
      p += v * step + Eigen::Vector2d(0.0, 0.5 * accel_mm_s2 * step * step);
      v.y() += accel_mm_s2 * step;
      t += step;
    }
    if (p.y() >= board.height_mm) break;
    RollingSample s;
    s.t_s = t_k;
    s.position_mm = p;
    s.velocity_mm_s = v;
    s.measured_mm = p + Eigen::Vector2d(noise(rng), noise(rng));
    out.push_back(s);
  }
  return out;
}

}  // namespace ephor::catching::testing
