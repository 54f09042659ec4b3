#include "common/catch/vision/ball_window.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ephor::catching {

BallWindow::BallWindow(const BoardSpec& board, const CameraIntrinsics& camera,
                       const Pose& board_to_camera, BallWindowOptions options)
    : projector_(board, camera), board_to_camera_(board_to_camera), options_(options) {
  if (!(options_.margin_px > 0.0) || !(options_.difference_gap_s > 0.0) ||
      !(options_.max_ahead_s >= 0.0))
    throw std::invalid_argument(
        "BallWindow: margin_px and difference_gap_s must be positive, max_ahead_s not negative");
}

std::optional<cv::Rect> BallWindow::around(const Eigen::Vector2d& position_b_mm,
                                           const Eigen::Vector2d& velocity_b_mm_s,
                                           double ahead_s) const {
  if (!(ahead_s >= 0.0) || ahead_s > options_.max_ahead_s) return std::nullopt;
  const double r = projector_.board().ball_radius_mm();
  const Eigen::Vector2d now_xy = position_b_mm + velocity_b_mm_s * ahead_s;
  const Eigen::Vector2d before_xy = now_xy - velocity_b_mm_s * options_.difference_gap_s;
  if (!now_xy.allFinite() || !before_xy.allFinite()) return std::nullopt;
  // Both positions must be in front of the camera for their pixels to mean anything.
  const Eigen::Vector3d now(now_xy.x(), now_xy.y(), r), before(before_xy.x(), before_xy.y(), r);
  if (!((board_to_camera_ * now).z() > 0.0) || !((board_to_camera_ * before).z() > 0.0))
    return std::nullopt;
  const Eigen::Vector2d a = projector_.project(board_to_camera_, now);
  const Eigen::Vector2d b = projector_.project(board_to_camera_, before);
  if (!a.allFinite() || !b.allFinite()) return std::nullopt;
  const CameraIntrinsics& camera = projector_.camera();
  // Clamp before converting: a point far outside the image must not overflow int.
  auto clamp_u = [&](double u) { return std::clamp(u, -1.0, static_cast<double>(camera.width)); };
  auto clamp_v = [&](double v) { return std::clamp(v, -1.0, static_cast<double>(camera.height)); };
  const double m = options_.margin_px;
  const cv::Rect r_px(cv::Point(static_cast<int>(std::floor(clamp_u(std::min(a.x(), b.x()) - m))),
                                static_cast<int>(std::floor(clamp_v(std::min(a.y(), b.y()) - m)))),
                      cv::Point(static_cast<int>(std::ceil(clamp_u(std::max(a.x(), b.x()) + m))),
                                static_cast<int>(std::ceil(clamp_v(std::max(a.y(), b.y()) + m)))));
  const cv::Rect clipped = r_px & cv::Rect(0, 0, camera.width, camera.height);
  if (clipped.area() <= 0) return std::nullopt;
  return clipped;
}

}  // namespace ephor::catching
