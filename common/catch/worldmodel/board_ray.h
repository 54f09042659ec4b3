#pragma once
// BoardRay: the paper's inverse perspective (paper 000, section 5.4). The
// ball's image centroid is turned into a ray from the camera's optical
// centre and intersected with the inclined board, giving the ball's 3-D
// position in the board frame B and, through board_to_world(), in the work
// cell W. The inverse (a point of B to a pixel) gives windows of interest.
//
// The centroid of the ball's image is (up to perspective, well under a
// pixel at these distances) the image of the ball's centre, and the centre
// rolls at z_B = +ball radius, not on the board face: intersecting with the
// face itself would place the ball too far from the camera along the ray,
// an error of r * |ray_xy| / |ray_z| in the board plane (see the test).
//
// Frames and units as in common/catch/board_model.h: lengths in mm,
// pixels with the origin at the centre of the top-left pixel. Distortion
// (OpenCV's k1 k2 p1 p2 [k3 ...]) is removed with cv::undistortPoints when
// the intrinsics have any non-zero coefficient.
//
// Immutable after construction; const methods are safe from any thread.

#include <optional>
#include <vector>

#include <Eigen/Core>

#include "common/catch/board_model.h"

namespace ephor::catching {

enum class RayStatus {
  kOk,
  kParallel,      // the ray runs (numerically) parallel to the plane
  kBehindCamera,  // the plane is met only behind the camera
  kNotFinite,     // non-finite pixel
};

const char* to_string(RayStatus status);

struct BoardRayHit {
  RayStatus status = RayStatus::kNotFinite;
  Eigen::Vector3d point_b_mm = Eigen::Vector3d::Zero();  // in B (z = the plane's height)
  Eigen::Vector3d point_w_mm = Eigen::Vector3d::Zero();  // the same point in W
  double range_mm = 0.0;  // distance from the camera centre to the point
  bool ok() const { return status == RayStatus::kOk; }
};

class BoardRay {
 public:
  // `board_to_camera`: the board's pose in the camera, p_C = R p_B + t (mm),
  // as the four-circle calibration estimates it. Throws
  // std::invalid_argument for non-positive focal lengths or a distortion
  // vector of a length OpenCV does not accept (0, 4, 5, 8, 12, 14).
  BoardRay(const BoardSpec& board, const BoardPlacement& placement,
           const CameraIntrinsics& intrinsics, const Pose& board_to_camera);

  // The ball centre seen at pixel (u, v): the ray meets the plane z_B = +r.
  BoardRayHit intersect(double u_px, double v_px) const;
  // The ray through (u, v) meets the plane z_B = z_b_mm (0 = the board face).
  BoardRayHit intersect_at_height(double u_px, double v_px, double z_b_mm) const;
  // The undistorted normalised image coordinates (x/z, y/z in C) of a pixel.
  Eigen::Vector2d normalised(double u_px, double v_px) const;
  // The pixel at which a point of B is seen (with distortion), or nullopt if
  // it is not in front of the camera.
  std::optional<Eigen::Vector2d> project(const Eigen::Vector3d& point_b_mm) const;

  bool has_distortion() const { return has_distortion_; }
  const Pose& board_to_camera() const { return board_to_camera_; }
  const Pose& camera_to_board() const { return camera_to_board_; }
  const Pose& board_to_world() const { return board_to_world_; }
  const BoardSpec& board() const { return board_; }

 private:
  BoardSpec board_;
  CameraIntrinsics intrinsics_;
  bool has_distortion_ = false;
  Pose board_to_camera_;
  Pose camera_to_board_;
  Pose board_to_world_;
};

}  // namespace ephor::catching
