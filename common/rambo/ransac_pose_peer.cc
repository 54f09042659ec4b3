#include "common/rambo/ransac_pose_peer.h"

#include <opencv2/calib3d.hpp>

namespace ephor::rambo {

RansacPosePeer::RansacPosePeer(TargetModel model, CameraIntrinsics camera)
    : model_(std::move(model)), camera_(camera) {}

std::optional<PeerPose> RansacPosePeer::estimate(const std::vector<ImageTriple>& triples) const {
  std::vector<Eigen::Vector2d> pts;
  auto add = [&pts](const Eigen::Vector2d& p) {
    if (!p.allFinite()) return;
    for (const auto& q : pts)
      if ((q - p).squaredNorm() < 1e-12) return;
    pts.push_back(p);
  };
  for (const auto& t : triples) add(t.reference_px), add(t.a_px), add(t.b_px);
  if (pts.size() < 4) return std::nullopt;
  std::vector<cv::Point3d> o;
  std::vector<cv::Point2d> i;
  for (const auto& p : pts)
    for (const auto& v : model_.vertices())
      o.emplace_back(v.x(), v.y(), v.z()), i.emplace_back(p.x(), p.y());
  const cv::Mat k = (cv::Mat_<double>(3, 3) << camera_.fx_px, 0, camera_.cx_px, 0, camera_.fy_px,
                     camera_.cy_px, 0, 0, 1);
  cv::Mat rvec, tvec;
  std::vector<int> inliers;
  if (!cv::solvePnPRansac(o, i, k, cv::noArray(), rvec, tvec, false, 20000, 3.0, 0.999, inliers,
                          cv::SOLVEPNP_AP3P))
    return std::nullopt;
  cv::Mat rm;
  cv::Rodrigues(rvec, rm);
  PeerPose out;
  for (int a = 0; a < 3; ++a) {
    for (int b = 0; b < 3; ++b) out.target_in_camera.linear()(a, b) = rm.at<double>(a, b);
    out.target_in_camera.translation()[a] = tvec.at<double>(a);
  }
  if (!out.target_in_camera.matrix().allFinite()) return std::nullopt;
  out.inliers = static_cast<int>(inliers.size());
  out.hypotheses = static_cast<int>(o.size());
  return out;
}

}  // namespace ephor::rambo
