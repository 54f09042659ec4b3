#include "common/catch/worldmodel/board_ray.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

namespace ephor::catching {

const char* to_string(RayStatus status) {
  switch (status) {
    case RayStatus::kOk:
      return "ok";
    case RayStatus::kParallel:
      return "parallel";
    case RayStatus::kBehindCamera:
      return "behind camera";
    case RayStatus::kNotFinite:
      return "not finite";
  }
  return "?";
}

BoardRay::BoardRay(const BoardSpec& board, const BoardPlacement& placement,
                   const CameraIntrinsics& intrinsics, const Pose& board_to_camera)
    : board_(board),
      intrinsics_(intrinsics),
      board_to_camera_(board_to_camera),
      camera_to_board_(board_to_camera.inverse()),
      board_to_world_(ephor::catching::board_to_world(board, placement)) {
  if (!(intrinsics.fx > 0.0) || !(intrinsics.fy > 0.0)) {
    throw std::invalid_argument(
        "BoardRay: focal lengths must be positive, got fx=" + std::to_string(intrinsics.fx) +
        " fy=" + std::to_string(intrinsics.fy));
  }
  const std::size_t n = intrinsics.distortion.size();
  if (n != 0 && n != 4 && n != 5 && n != 8 && n != 12 && n != 14) {
    throw std::invalid_argument(
        "BoardRay: OpenCV takes 4, 5, 8, 12 or 14 distortion coefficients, got " +
        std::to_string(n));
  }
  for (double k : intrinsics.distortion) {
    if (k != 0.0) has_distortion_ = true;
  }
}

Eigen::Vector2d BoardRay::normalised(double u_px, double v_px) const {
  if (!has_distortion_) {
    return {(u_px - intrinsics_.cx) / intrinsics_.fx, (v_px - intrinsics_.cy) / intrinsics_.fy};
  }
  // Wrap stack buffers so that OpenCV allocates nothing but its own scratch.
  double in[2] = {u_px, v_px};
  double out[2] = {0.0, 0.0};
  const cv::Mat src(1, 1, CV_64FC2, in);
  cv::Mat dst(1, 1, CV_64FC2, out);
  const cv::Matx33d k(intrinsics_.fx, 0.0, intrinsics_.cx, 0.0, intrinsics_.fy, intrinsics_.cy, 0.0,
                      0.0, 1.0);
  const cv::Mat dist(1, static_cast<int>(intrinsics_.distortion.size()), CV_64F,
                     const_cast<double*>(intrinsics_.distortion.data()));
  // The default of 5 iterations leaves ~0.1 px at the corners of a strongly
  // distorted lens; iterate to 1e-9 px (the error is measured in pixels).
  cv::undistortPoints(src, dst, k, dist, cv::noArray(), cv::noArray(),
                      cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 100, 1e-9));
  return {out[0], out[1]};
}

BoardRayHit BoardRay::intersect(double u_px, double v_px) const {
  return intersect_at_height(u_px, v_px, board_.ball_radius_mm());
}

BoardRayHit BoardRay::intersect_at_height(double u_px, double v_px, double z_b_mm) const {
  BoardRayHit hit;
  if (!std::isfinite(u_px) || !std::isfinite(v_px) || !std::isfinite(z_b_mm)) {
    hit.status = RayStatus::kNotFinite;
    return hit;
  }
  const Eigen::Vector2d m = normalised(u_px, v_px);
  // The ray in B: origin o (the camera centre), direction d.
  const Eigen::Vector3d o = camera_to_board_.translation();
  const Eigen::Vector3d d = camera_to_board_.linear() * Eigen::Vector3d(m.x(), m.y(), 1.0);
  // o.z + s d.z = z_b. A grazing ray (under 1e-9 rad from the plane) gives
  // no usable point.
  if (std::abs(d.z()) <= 1e-9 * d.norm()) {
    hit.status = RayStatus::kParallel;
    return hit;
  }
  const double s = (z_b_mm - o.z()) / d.z();
  if (!(s > 0.0)) {
    hit.status = RayStatus::kBehindCamera;
    return hit;
  }
  hit.status = RayStatus::kOk;
  hit.point_b_mm = o + s * d;
  hit.point_b_mm.z() = z_b_mm;  // exact, not o.z + s d.z's rounding
  hit.point_w_mm = board_to_world_ * hit.point_b_mm;
  hit.range_mm = s * d.norm();
  return hit;
}

std::optional<Eigen::Vector2d> BoardRay::project(const Eigen::Vector3d& point_b_mm) const {
  const Eigen::Vector3d p = board_to_camera_ * point_b_mm;
  if (!(p.z() > 0.0)) return std::nullopt;
  if (!has_distortion_) {
    return Eigen::Vector2d(intrinsics_.fx * p.x() / p.z() + intrinsics_.cx,
                           intrinsics_.fy * p.y() / p.z() + intrinsics_.cy);
  }
  const std::vector<cv::Point3d> object{{p.x(), p.y(), p.z()}};
  std::vector<cv::Point2d> image;
  const cv::Matx33d k(intrinsics_.fx, 0.0, intrinsics_.cx, 0.0, intrinsics_.fy, intrinsics_.cy, 0.0,
                      0.0, 1.0);
  cv::projectPoints(object, cv::Vec3d(0.0, 0.0, 0.0), cv::Vec3d(0.0, 0.0, 0.0), k,
                    intrinsics_.distortion, image);
  return Eigen::Vector2d(image[0].x, image[0].y);
}

}  // namespace ephor::catching
