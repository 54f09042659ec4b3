#pragma once
// BoardPoseEstimator: the board-to-camera pose from the image centroids of
// the board's four circles (paper 000, section 3: "a four coplanar point
// algorithm"). Planar PnP by IPPE (cv::solvePnPGeneric, SOLVEPNP_IPPE) with
// both of its solutions examined, or OpenCV's iterative PnP as the peer.
//
// Perspective bias: the area centroid of a circle's image (an ellipse) is
// not the image of the circle's centre; at oblique views the difference is
// tenths of a pixel and biases the pose. With the current pose each circle's
// projected ellipse is computed analytically (the conic H^-T Q H^-1), the
// difference (ellipse centroid - projected centre) is subtracted from the
// measured centroid and the pose re-solved, bias_iterations times.
//
// Frames (board_model.h): B board (mm), C camera (OpenCV pinhole), image px
// with the origin at the centre of the top-left pixel. Immutable; safe to
// share between threads.

#include <array>
#include <string>

#include <Eigen/Core>

#include "common/catch/board_model.h"

namespace ephor::catching {

enum class PnpMethod { kIppe, kIterative };

struct BoardPoseOptions {
  PnpMethod method = PnpMethod::kIppe;
  int bias_iterations = 3;  // 0: take the centroids as images of the centres
};

struct BoardPoseResult {
  bool ok = false;
  std::string problem;  // why not ok ("no solution puts the board in front of the camera")
  Pose board_to_camera = Pose::Identity();  // p_C = R p_B + t, mm
  // RMS (px) of (bias-corrected centroid - projected centre) at the final pose.
  double reprojection_rms_px = 0.0;
  // Per circle (board order), the perspective bias of a measured centroid at
  // the final pose: projected-ellipse centroid - projected centre (px). This
  // is what was subtracted; zero when bias_iterations = 0.
  std::array<Eigen::Vector2d, 4> bias_px{};
  // IPPE only: which of solvePnPGeneric's two solutions (0: lower error) was
  // kept in the last solve, both solutions' RMS (px; +inf when one puts the
  // board behind the camera or shows its back), and rejected / kept.
  int ippe_solution = -1;
  std::array<double, 2> ippe_rms_px{};
  double ippe_error_ratio = 0.0;
  int solves = 0;  // PnP solves done
};

// A circle of B as the ideal pinhole camera sees it.
struct ProjectedCircle {
  Eigen::Vector2d centre_px;    // image of the circle's centre
  Eigen::Vector2d centroid_px;  // area centroid (= centre) of the image ellipse
  double area_px = 0.0;         // area of the image ellipse, px^2 (NaN if not an ellipse)
};

class BoardPoseEstimator {
 public:
  BoardPoseEstimator(const BoardSpec& board, const CameraIntrinsics& camera);

  // Pose from the measured centroids of circles[0..3] (board order, px, as
  // the distorted camera sees them: they are undistorted first). Throws
  // std::invalid_argument on a non-finite centroid.
  BoardPoseResult estimate(const std::array<Eigen::Vector2d, 4>& centroids_px,
                           const BoardPoseOptions& options = {}) const;

  // Projection of a point of B (px) with the camera's distortion.
  Eigen::Vector2d project(const Pose& board_to_camera, const Eigen::Vector3d& p_b_mm) const;
  // Circle `index` (0..3) through the ideal (undistorted) pinhole.
  ProjectedCircle project_circle(const Pose& board_to_camera, int index) const;
  // Any circle of the board plane (centre x, y and radius in mm of B).
  ProjectedCircle project_circle(const Pose& board_to_camera, double x_mm, double y_mm,
                                 double radius_mm) const;

  const BoardSpec& board() const { return board_; }
  const CameraIntrinsics& camera() const { return camera_; }

 private:
  BoardSpec board_;
  CameraIntrinsics camera_;
};

}  // namespace ephor::catching
