#pragma once
// BoardProjector: points of the catching cell into the camera image, for the
// page's overlays. Board frame B through the board's pose in the camera
// (catch_board_pose_t from ephor-catch-vision: p_C = R p_B + t); work cell
// frame W through B as well, once the survey placed the board in W
// (catch_survey_t, board_model.h's board_to_world): p_C = R (T_WB^-1 p_W) + t.
// Pinhole with OpenCV's distortion (cv::projectPoints), intrinsics from the
// camera file. Frames and units of common/catch/board_model.h: mm, px.
//
// Pure; not thread-safe.

#include <optional>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "common/catch/board_model.h"

namespace ephor::catch_display {

class BoardProjector {
 public:
  explicit BoardProjector(catching::CameraIntrinsics camera);

  // The board's pose in the camera (p_C = board_to_camera * p_B); nullopt = unknown.
  void set_board_to_camera(std::optional<catching::Pose> board_to_camera);
  // The board's pose in the work cell (p_W = board_to_world * p_B); nullopt = unknown.
  void set_board_to_world(std::optional<catching::Pose> board_to_world);

  bool knows_board() const { return board_to_camera_.has_value(); }
  bool knows_world() const { return board_to_camera_ && world_to_board_; }

  // The image point (px) of a point in B / in W; nullopt when its frame's
  // pose is unknown, the point is not finite, or it is not in front of the
  // camera (z_C below 1 mm).
  std::optional<Eigen::Vector2d> project_board(const Eigen::Vector3d& p_b_mm) const;
  std::optional<Eigen::Vector2d> project_world(const Eigen::Vector3d& p_w_mm) const;

  const catching::CameraIntrinsics& camera() const { return camera_; }

 private:
  std::optional<Eigen::Vector2d> project_camera(const Eigen::Vector3d& p_c_mm) const;

  catching::CameraIntrinsics camera_;
  std::optional<catching::Pose> board_to_camera_;
  std::optional<catching::Pose> world_to_board_;
};

}  // namespace ephor::catch_display
