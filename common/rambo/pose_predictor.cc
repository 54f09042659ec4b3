#include "common/rambo/pose_predictor.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace ephor::rambo {

PosePrediction PosePredictor::predict_goal(const Eigen::Isometry3d& goal_in_target,
                                           double t_s) const {
  PosePrediction target = predict(t_s);
  PosePrediction g;
  g.pose = target.pose * goal_in_target;
  const double lever = goal_in_target.translation().norm() * target.rotation_sigma_rad;
  g.position_sigma_mm = std::hypot(target.position_sigma_mm, lever);
  g.rotation_sigma_rad = target.rotation_sigma_rad;
  return g;
}

std::vector<PosePrediction> PosePredictor::goal_trajectory(const Eigen::Isometry3d& goal_in_target,
                                                           double t0_s, double dt_s, int n) const {
  std::vector<PosePrediction> out;
  out.reserve(static_cast<std::size_t>(std::max(n, 0)));
  for (int k = 0; k < n; ++k) out.push_back(predict_goal(goal_in_target, t0_s + dt_s * k));
  return out;
}

bool check_samples(const std::vector<PoseSample>& samples, std::size_t min_samples,
                   std::string* why) {
  auto fail = [why](const std::string& s) {
    if (why) *why = s;
    return false;
  };
  if (samples.size() < min_samples) {
    std::ostringstream o;
    o << "need at least " << min_samples << " pose samples, got " << samples.size();
    return fail(o.str());
  }
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const auto& s = samples[i];
    if (!std::isfinite(s.t_s) || !s.pose.matrix().allFinite())
      return fail("pose sample " + std::to_string(i) + " is not finite");
    if (i > 0 && !(s.t_s > samples[i - 1].t_s))
      return fail("pose sample " + std::to_string(i) + " is not later than the one before");
    const Eigen::Matrix3d r = s.pose.linear();
    if ((r.transpose() * r - Eigen::Matrix3d::Identity()).norm() > 1e-6 || r.determinant() < 0.0)
      return fail("pose sample " + std::to_string(i) + " has a rotation that is not orthonormal");
  }
  return true;
}

Eigen::Vector3d zyx_angles(const Eigen::Matrix3d& r) {
  const double pitch = std::asin(std::clamp(-r(2, 0), -1.0, 1.0));
  const double yaw = std::atan2(r(1, 0), r(0, 0));
  const double roll = std::atan2(r(2, 1), r(2, 2));
  return {yaw, pitch, roll};
}

Eigen::Matrix3d from_zyx_angles(const Eigen::Vector3d& ypr) {
  return (Eigen::AngleAxisd(ypr[0], Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(ypr[1], Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(ypr[2], Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

double rotation_angle_between(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return Eigen::AngleAxisd(a.transpose() * b).angle();
}

}  // namespace ephor::rambo
