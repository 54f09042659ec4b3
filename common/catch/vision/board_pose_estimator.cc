#include "common/catch/vision/board_pose_estimator.h"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include <Eigen/Dense>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

namespace ephor::catching {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kInf = std::numeric_limits<double>::infinity();

cv::Matx33d camera_matrix(const CameraIntrinsics& c) {
  return {c.fx, 0.0, c.cx, 0.0, c.fy, c.cy, 0.0, 0.0, 1.0};
}

Pose to_pose(const cv::Mat& rvec, const cv::Mat& tvec) {
  cv::Matx33d r;
  cv::Rodrigues(rvec, r);
  Pose p = Pose::Identity();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) p.linear()(i, j) = r(i, j);
    p.translation()(i) = tvec.at<double>(i);
  }
  return p;
}

// The board is seen from its face side and every circle is in front.
bool physically_seen(const Pose& pose, const std::vector<cv::Point3d>& object) {
  const Eigen::Vector3d camera_in_b = -pose.linear().transpose() * pose.translation();
  if (!(camera_in_b.z() > 0.0)) return false;
  for (const auto& p : object)
    if (!((pose * Eigen::Vector3d(p.x, p.y, p.z)).z() > 0.0)) return false;
  return true;
}

double rms(const Pose& pose, const cv::Matx33d& k, const std::vector<cv::Point3d>& object,
           const std::vector<cv::Point2d>& image) {
  double sum = 0.0;
  for (size_t i = 0; i < object.size(); ++i) {
    const Eigen::Vector3d p = pose * Eigen::Vector3d(object[i].x, object[i].y, object[i].z);
    const double u = k(0, 0) * p.x() / p.z() + k(0, 2), v = k(1, 1) * p.y() / p.z() + k(1, 2);
    sum += (u - image[i].x) * (u - image[i].x) + (v - image[i].y) * (v - image[i].y);
  }
  return std::sqrt(sum / static_cast<double>(object.size()));
}

struct IppeSolutions {
  std::vector<Pose> poses;  // board to camera, OpenCV's order (lower error first)
  double angle_rad = kInf;  // rotation angle of the first, in the frame solved in
};

// IPPE in B, or in B turned half a turn about its z axis (x, y -> -x, -y).
IppeSolutions solve_ippe(const std::vector<cv::Point3d>& object,
                         const std::vector<cv::Point2d>& image, const cv::Matx33d& k, bool turned) {
  std::vector<cv::Point3d> obj = object;
  if (turned)
    for (auto& p : obj) p = {-p.x, -p.y, p.z};
  std::vector<cv::Mat> rvecs, tvecs;
  cv::solvePnPGeneric(obj, image, k, cv::noArray(), rvecs, tvecs, false, cv::SOLVEPNP_IPPE);
  IppeSolutions out;
  Pose turn = Pose::Identity();
  if (turned) turn.linear() = Eigen::Vector3d(-1.0, -1.0, 1.0).asDiagonal();
  for (size_t i = 0; i < rvecs.size(); ++i) {
    out.poses.push_back(to_pose(rvecs[i], tvecs[i]) * turn);
    if (i == 0) out.angle_rad = cv::norm(rvecs[i]);
  }
  return out;
}

}  // namespace

BoardPoseEstimator::BoardPoseEstimator(const BoardSpec& board, const CameraIntrinsics& camera)
    : board_(board), camera_(camera) {}

ProjectedCircle BoardPoseEstimator::project_circle(const Pose& pose, int index) const {
  const BoardCircle& c = board_.circles.at(static_cast<size_t>(index));
  return project_circle(pose, c.x_mm, c.y_mm, c.diameter_mm / 2.0);
}

ProjectedCircle BoardPoseEstimator::project_circle(const Pose& pose, double x0, double y0,
                                                   double r) const {
  Eigen::Matrix3d k;
  k << camera_.fx, 0.0, camera_.cx, 0.0, camera_.fy, camera_.cy, 0.0, 0.0, 1.0;
  Eigen::Matrix3d rt;
  rt.col(0) = pose.linear().col(0);
  rt.col(1) = pose.linear().col(1);
  rt.col(2) = pose.translation();
  const Eigen::Matrix3d h = k * rt;  // board plane (x, y, 1) -> image (homogeneous)
  Eigen::Matrix3d q;
  q << 1.0, 0.0, -x0, 0.0, 1.0, -y0, -x0, -y0, x0 * x0 + y0 * y0 - r * r;
  const Eigen::Matrix3d h_inv = h.inverse();
  Eigen::Matrix3d conic = h_inv.transpose() * q * h_inv;
  conic /= conic.cwiseAbs().maxCoeff();
  ProjectedCircle out;
  const Eigen::Vector3d centre = h * Eigen::Vector3d(x0, y0, 1.0);
  out.centre_px = centre.head<2>() / centre.z();
  Eigen::Matrix2d a = conic.topLeftCorner<2, 2>();
  Eigen::Vector2d d = conic.topRightCorner<2, 1>();
  double f = conic(2, 2);
  if (a.determinant() <= 0.0) {  // the circle crosses the horizon: no ellipse
    out.centroid_px = Eigen::Vector2d::Constant(std::numeric_limits<double>::quiet_NaN());
    out.area_px = std::numeric_limits<double>::quiet_NaN();
    return out;
  }
  if (a.trace() < 0.0) {
    a = -a;
    d = -d;
    f = -f;
  }
  const Eigen::Vector2d a_inv_d = a.inverse() * d;
  out.centroid_px = -a_inv_d;
  const double kappa = d.dot(a_inv_d) - f;
  out.area_px = kPi * kappa / std::sqrt(a.determinant());
  return out;
}

Eigen::Vector2d BoardPoseEstimator::project(const Pose& pose, const Eigen::Vector3d& p_b) const {
  const Eigen::Vector3d p = pose * p_b;
  std::vector<cv::Point3d> in{{p.x(), p.y(), p.z()}};
  std::vector<cv::Point2d> out;
  cv::projectPoints(in, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), camera_matrix(camera_),
                    camera_.distortion, out);
  return {out[0].x, out[0].y};
}

BoardPoseResult BoardPoseEstimator::estimate(const std::array<Eigen::Vector2d, 4>& centroids_px,
                                             const BoardPoseOptions& options) const {
  for (const auto& c : centroids_px)
    if (!c.allFinite()) throw std::invalid_argument("board pose: a circle centroid is not finite");
  const cv::Matx33d k = camera_matrix(camera_);
  std::vector<cv::Point3d> object;
  for (const BoardCircle& c : board_.circles) object.emplace_back(c.x_mm, c.y_mm, 0.0);
  // Measured centroids as the ideal pinhole would see them.
  std::vector<cv::Point2d> measured;
  for (const auto& c : centroids_px) measured.emplace_back(c.x(), c.y());
  if (!camera_.distortion.empty()) {
    std::vector<cv::Point2d> undistorted;
    cv::undistortPoints(measured, undistorted, k, camera_.distortion, cv::noArray(), k);
    measured = undistorted;
  }

  BoardPoseResult result;
  result.bias_px.fill(Eigen::Vector2d::Zero());
  std::vector<cv::Point2d> corrected = measured;
  cv::Mat rvec, tvec;
  bool have_guess = false;
  for (int iteration = 0; iteration <= std::max(0, options.bias_iterations); ++iteration) {
    if (options.method == PnpMethod::kIppe) {
      // OpenCV returns IPPE's rotations as Rodrigues vectors, which are
      // unreliable near 180 degrees, and an upright camera facing the board
      // is about 180 degrees from B (B's x runs to the left in the image).
      // Solve in B and in B turned half a turn about z, keep the frame whose
      // rotation is farther from 180 degrees.
      IppeSolutions best_frame;
      for (const bool turned : {true, false}) {
        IppeSolutions s = solve_ippe(object, corrected, k, turned);
        ++result.solves;
        if (s.poses.empty()) continue;
        if (best_frame.poses.empty() || s.angle_rad < best_frame.angle_rad) best_frame = s;
      }
      result.ippe_rms_px = {kInf, kInf};
      int best = -1;
      for (size_t i = 0; i < best_frame.poses.size() && i < 2; ++i) {
        const Pose& p = best_frame.poses[i];
        if (!physically_seen(p, object)) continue;
        result.ippe_rms_px[i] = rms(p, k, object, corrected);
        if (best < 0 || result.ippe_rms_px[i] < result.ippe_rms_px[static_cast<size_t>(best)])
          best = static_cast<int>(i);
      }
      if (best < 0) {
        result.ok = false;
        result.problem = "no IPPE solution puts the board in front of the camera, face on";
        return result;
      }
      result.ippe_solution = best;
      const double kept = result.ippe_rms_px[static_cast<size_t>(best)];
      const double other = result.ippe_rms_px[static_cast<size_t>(1 - best)];
      result.ippe_error_ratio = other / std::max(kept, 1e-12);
      result.board_to_camera = best_frame.poses[static_cast<size_t>(best)];
    } else {
      if (!have_guess) {
        rvec = cv::Mat();
        tvec = cv::Mat();
      }
      if (!cv::solvePnP(object, corrected, k, cv::noArray(), rvec, tvec, have_guess,
                        cv::SOLVEPNP_ITERATIVE)) {
        result.ok = false;
        result.problem = "iterative PnP failed";
        return result;
      }
      ++result.solves;
      have_guess = true;
      if (!physically_seen(to_pose(rvec, tvec), object)) {
        result.ok = false;
        result.problem = "iterative PnP put the board behind the camera or showed its back";
        return result;
      }
      result.board_to_camera = to_pose(rvec, tvec);
    }
    if (iteration == options.bias_iterations) break;
    for (size_t i = 0; i < 4; ++i) {
      const ProjectedCircle pc = project_circle(result.board_to_camera, static_cast<int>(i));
      if (!pc.centroid_px.allFinite()) continue;
      result.bias_px[i] = pc.centroid_px - pc.centre_px;
      corrected[i] = {measured[i].x - result.bias_px[i].x(), measured[i].y - result.bias_px[i].y()};
    }
  }
  result.reprojection_rms_px = rms(result.board_to_camera, k, object, corrected);
  result.ok = true;
  return result;
}

}  // namespace ephor::catching
