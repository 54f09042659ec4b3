#include "procs/catch/display/board_projector.h"

#include <vector>

#include <opencv2/calib3d.hpp>

namespace ephor::catch_display {

BoardProjector::BoardProjector(catching::CameraIntrinsics camera) : camera_(std::move(camera)) {}

void BoardProjector::set_board_to_camera(std::optional<catching::Pose> board_to_camera) {
  board_to_camera_ = board_to_camera;
}

void BoardProjector::set_board_to_world(std::optional<catching::Pose> board_to_world) {
  if (board_to_world) {
    world_to_board_ = board_to_world->inverse();
  } else {
    world_to_board_.reset();
  }
}

std::optional<Eigen::Vector2d> BoardProjector::project_camera(const Eigen::Vector3d& p) const {
  if (!p.allFinite() || p.z() < 1.0) return std::nullopt;
  if (camera_.distortion.empty()) {
    return Eigen::Vector2d(camera_.fx * p.x() / p.z() + camera_.cx,
                           camera_.fy * p.y() / p.z() + camera_.cy);
  }
  const std::vector<cv::Point3d> in{{p.x(), p.y(), p.z()}};
  std::vector<cv::Point2d> out;
  const cv::Matx33d k(camera_.fx, 0, camera_.cx, 0, camera_.fy, camera_.cy, 0, 0, 1);
  cv::projectPoints(in, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), k, camera_.distortion, out);
  return Eigen::Vector2d(out[0].x, out[0].y);
}

std::optional<Eigen::Vector2d> BoardProjector::project_board(const Eigen::Vector3d& p_b) const {
  if (!board_to_camera_) return std::nullopt;
  return project_camera(*board_to_camera_ * p_b);
}

std::optional<Eigen::Vector2d> BoardProjector::project_world(const Eigen::Vector3d& p_w) const {
  if (!board_to_camera_ || !world_to_board_) return std::nullopt;
  return project_camera(*board_to_camera_ * (*world_to_board_ * p_w));
}

}  // namespace ephor::catch_display
