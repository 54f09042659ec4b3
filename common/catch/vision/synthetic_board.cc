#include "common/catch/vision/synthetic_board.h"

#include <algorithm>
#include <cmath>
#include <random>

namespace ephor::catching {
namespace {

constexpr double kPi = 3.14159265358979323846;

enum Label : int { kBackground = 0, kBoard = 1, kCircle0 = 2, kBall = 6 };

class RayCaster {
 public:
  explicit RayCaster(const SyntheticScene& s)
      : s_(s),
        r_bc_(s.board_to_camera.linear().transpose()),
        c_b_(-r_bc_ * s.board_to_camera.translation()) {
    for (int i = 0; i < 4; ++i)
      covered_[static_cast<size_t>(i)] =
          std::find(s.covered_circles.begin(), s.covered_circles.end(), i) !=
          s.covered_circles.end();
    if (s.ball)
      ball_centre_ =
          Eigen::Vector3d(s.ball->xy_b_mm.x(), s.ball->xy_b_mm.y(), s.board.ball_radius_mm());
  }

  int label(double u, double v) const {
    const Eigen::Vector3d d_c((u - s_.camera.cx) / s_.camera.fx, (v - s_.camera.cy) / s_.camera.fy,
                              1.0);
    const Eigen::Vector3d d = r_bc_ * d_c;
    if (s_.ball) {
      const double r = s_.board.ball_radius_mm();
      const Eigen::Vector3d oc = c_b_ - ball_centre_;
      const double a = d.squaredNorm(), h = oc.dot(d), c = oc.squaredNorm() - r * r;
      const double disc = h * h - a * c;
      if (disc >= 0.0 && (-h - std::sqrt(disc)) / a > 0.0) return kBall;
    }
    if (!(d.z() < 0.0) || !(c_b_.z() > 0.0)) return kBackground;
    const double t = -c_b_.z() / d.z();
    const double x = c_b_.x() + t * d.x(), y = c_b_.y() + t * d.y();
    if (!s_.board.on_board(x, y)) return kBackground;
    for (int i = 0; i < 4; ++i) {
      const BoardCircle& ci = s_.board.circles[static_cast<size_t>(i)];
      const double r = ci.diameter_mm / 2.0;
      if (!covered_[static_cast<size_t>(i)] &&
          (x - ci.x_mm) * (x - ci.x_mm) + (y - ci.y_mm) * (y - ci.y_mm) <= r * r)
        return kCircle0 + i;
    }
    return kBoard;
  }

  double grey(int label) const {
    if (label == kBackground) return s_.background_grey;
    if (label == kBoard) return s_.board_grey;
    if (label == kBall) return s_.board_grey + s_.ball->contrast;
    return s_.circle_grey;
  }

 private:
  const SyntheticScene& s_;
  Eigen::Matrix3d r_bc_;
  Eigen::Vector3d c_b_;
  Eigen::Vector3d ball_centre_ = Eigen::Vector3d::Zero();
  std::array<bool, 4> covered_{};
};

}  // namespace

cv::Mat render_board(const SyntheticScene& scene, double noise_sigma, uint64_t seed) {
  const int w = scene.camera.width, h = scene.camera.height;
  const RayCaster caster(scene);
  // Labels at pixel corners: pixel (i, j) spans u in [i - 0.5, i + 0.5].
  std::vector<int> corner(static_cast<size_t>((w + 1) * (h + 1)));
  for (int j = 0; j <= h; ++j)
    for (int i = 0; i <= w; ++i)
      corner[static_cast<size_t>(j * (w + 1) + i)] = caster.label(i - 0.5, j - 0.5);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, noise_sigma > 0.0 ? noise_sigma : 1.0);
  const int n = std::max(1, scene.edge_supersample);
  cv::Mat out(h, w, CV_8U);
  for (int j = 0; j < h; ++j) {
    auto* row = out.ptr<uint8_t>(j);
    for (int i = 0; i < w; ++i) {
      const int a = corner[static_cast<size_t>(j * (w + 1) + i)];
      const int b = corner[static_cast<size_t>(j * (w + 1) + i + 1)];
      const int c = corner[static_cast<size_t>((j + 1) * (w + 1) + i)];
      const int d = corner[static_cast<size_t>((j + 1) * (w + 1) + i + 1)];
      double value;
      if (a == b && a == c && a == d) {
        value = caster.grey(a);
      } else {
        double sum = 0.0;
        for (int sj = 0; sj < n; ++sj)
          for (int si = 0; si < n; ++si)
            sum += caster.grey(caster.label(i - 0.5 + (si + 0.5) / n, j - 0.5 + (sj + 0.5) / n));
        value = sum / (n * n);
      }
      if (noise_sigma > 0.0) value += noise(rng);
      row[i] = static_cast<uint8_t>(std::clamp(std::lround(value), 0L, 255L));
    }
  }
  return out;
}

Pose look_at_board(const BoardSpec& board, double distance_mm, double tilt_deg, double pan_deg,
                   double roll_deg) {
  const double tilt = tilt_deg * kPi / 180.0, pan = pan_deg * kPi / 180.0,
               roll = roll_deg * kPi / 180.0;
  const Eigen::Vector3d centre(board.width_mm / 2.0, board.height_mm / 2.0, 0.0);
  // Direction from the centre to the camera: the normal tilted towards +y,
  // then turned about the normal.
  const Eigen::Vector3d dir(std::sin(tilt) * std::sin(pan), std::sin(tilt) * std::cos(pan),
                            std::cos(tilt));
  const Eigen::Vector3d c_b = centre + distance_mm * dir;
  const Eigen::Vector3d z_c = -dir;
  Eigen::Vector3d x_c = Eigen::Vector3d(-1.0, 0.0, 0.0);
  x_c = (x_c - x_c.dot(z_c) * z_c).normalized();
  Eigen::Vector3d y_c = z_c.cross(x_c);
  const Eigen::Vector3d x_r = std::cos(roll) * x_c + std::sin(roll) * y_c;
  const Eigen::Vector3d y_r = -std::sin(roll) * x_c + std::cos(roll) * y_c;
  Eigen::Matrix3d r_cb;
  r_cb.row(0) = x_r.transpose();
  r_cb.row(1) = y_r.transpose();
  r_cb.row(2) = z_c.transpose();
  Pose pose = Pose::Identity();
  pose.linear() = r_cb;
  pose.translation() = -r_cb * c_b;
  return pose;
}

Eigen::Vector2d project_pinhole(const CameraIntrinsics& camera, const Pose& board_to_camera,
                                const Eigen::Vector3d& p_b_mm) {
  const Eigen::Vector3d p = board_to_camera * p_b_mm;
  return {camera.fx * p.x() / p.z() + camera.cx, camera.fy * p.y() / p.z() + camera.cy};
}

}  // namespace ephor::catching
