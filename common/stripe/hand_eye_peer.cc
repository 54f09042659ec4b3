#include "common/stripe/hand_eye_peer.h"

#include <algorithm>
#include <numbers>
#include <stdexcept>

#include <opencv2/calib3d.hpp>

namespace ephor::stripe {

namespace {

cv::Mat rotation(const Eigen::Isometry3d& t) {
  cv::Mat r(3, 3, CV_64F);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r.at<double>(i, j) = t.linear()(i, j);
  return r;
}

// OpenCV is given metres (solve_hand_eye's note), we keep mm.
cv::Mat translation(const Eigen::Isometry3d& t) {
  cv::Mat v(3, 1, CV_64F);
  for (int i = 0; i < 3; ++i) v.at<double>(i) = 1e-3 * t.translation()(i);
  return v;
}

Eigen::Isometry3d pose(const cv::Mat& r, const cv::Mat& t) {
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) out.linear()(i, j) = r.at<double>(i, j);
    out.translation()(i) = 1e3 * t.at<double>(i);
  }
  return out;
}

}  // namespace

std::vector<HandEyeView> views_within(const std::vector<HandEyeView>& views, double max_deg) {
  const double max_rad = max_deg * std::numbers::pi / 180.0;
  auto angle = [&](size_t a, size_t b) {
    return Eigen::AngleAxisd(views[a].flange_in_base.linear().transpose() *
                             views[b].flange_in_base.linear())
        .angle();
  };
  std::vector<size_t> best;
  for (size_t seed = 0; seed < views.size(); ++seed) {
    std::vector<size_t> kept = {seed};
    for (size_t v = 0; v < views.size(); ++v) {
      if (v == seed) continue;
      bool ok = true;
      for (size_t k : kept) {
        if (angle(v, k) >= max_rad) {
          ok = false;
          break;
        }
      }
      if (ok) kept.push_back(v);
    }
    if (kept.size() > best.size()) best = kept;
  }
  std::sort(best.begin(), best.end());
  std::vector<HandEyeView> out;
  for (size_t k : best) out.push_back(views[k]);
  return out;
}

const char* hand_eye_method_name(HandEyeMethod method) {
  switch (method) {
    case HandEyeMethod::kTsai:
      return "TSAI";
    case HandEyeMethod::kPark:
      return "PARK";
    case HandEyeMethod::kHoraud:
      return "HORAUD";
    case HandEyeMethod::kAndreff:
      return "ANDREFF";
    case HandEyeMethod::kDaniilidis:
      return "DANIILIDIS";
    case HandEyeMethod::kShah:
      return "SHAH";
    case HandEyeMethod::kLi:
      return "LI";
  }
  return "?";
}

Eigen::Isometry3d solve_hand_eye(const std::vector<HandEyeView>& views, HandEyeMethod method) {
  if (views.size() < 3)
    throw std::invalid_argument("hand-eye: " + std::to_string(views.size()) +
                                " views of the target (need 3)");
  std::vector<cv::Mat> r_a, t_a, r_b, t_b;
  const bool robot_world = method == HandEyeMethod::kShah || method == HandEyeMethod::kLi;
  for (const HandEyeView& v : views) {
    // calibrateHandEye: gripper -> base and target -> camera;
    // calibrateRobotWorldHandEye: world (target) -> camera and base -> gripper.
    const Eigen::Isometry3d a = robot_world ? v.flange_in_base.inverse() : v.flange_in_base;
    r_a.push_back(rotation(a));
    t_a.push_back(translation(a));
    r_b.push_back(rotation(v.target_in_camera));
    t_b.push_back(translation(v.target_in_camera));
  }
  cv::Mat r, t;
  if (robot_world) {
    cv::Mat r_base2world, t_base2world;
    cv::calibrateRobotWorldHandEye(r_b, t_b, r_a, t_a, r_base2world, t_base2world, r, t,
                                   method == HandEyeMethod::kShah
                                       ? cv::CALIB_ROBOT_WORLD_HAND_EYE_SHAH
                                       : cv::CALIB_ROBOT_WORLD_HAND_EYE_LI);
    return pose(r, t).inverse();  // gripper -> camera, turned round
  }
  cv::HandEyeCalibrationMethod m = cv::CALIB_HAND_EYE_TSAI;
  switch (method) {
    case HandEyeMethod::kPark:
      m = cv::CALIB_HAND_EYE_PARK;
      break;
    case HandEyeMethod::kHoraud:
      m = cv::CALIB_HAND_EYE_HORAUD;
      break;
    case HandEyeMethod::kAndreff:
      m = cv::CALIB_HAND_EYE_ANDREFF;
      break;
    case HandEyeMethod::kDaniilidis:
      m = cv::CALIB_HAND_EYE_DANIILIDIS;
      break;
    default:
      break;
  }
  cv::calibrateHandEye(r_a, t_a, r_b, t_b, r, t, m);
  return pose(r, t);  // camera -> gripper
}

}  // namespace ephor::stripe
