#include "common/rambo/tumbling_body.h"

#include <stdexcept>

#include "common/rambo/rigid_body_pose_predictor.h"

namespace ephor::rambo {

TumblingBody::TumblingBody(const Eigen::Isometry3d& pose0, const Eigen::Vector3d& velocity_mm_s,
                           const Eigen::Vector3d& body_rates_rad_s,
                           const Eigen::Vector3d& principal_moments, double step_s)
    : pose0_(pose0),
      v_(velocity_mm_s),
      w0_(body_rates_rad_s),
      moments_(principal_moments),
      step_s_(step_s),
      q_(pose0.linear()),
      w_(body_rates_rad_s) {
  if (!pose0.matrix().allFinite() || !v_.allFinite() || !w0_.allFinite() || !moments_.allFinite() ||
      moments_.minCoeff() <= 0.0 || !(step_s > 0.0))
    throw std::invalid_argument("TumblingBody: non-finite state, moments <= 0 or step <= 0");
}

void TumblingBody::advance_to(double t_s) {
  if (t_s < t_) {  // restart from t = 0
    t_ = 0.0;
    q_ = Eigen::Quaterniond(pose0_.linear());
    w_ = w0_;
  }
  RigidBodyPosePredictor::propagate(moments_, step_s_, t_s - t_, &q_, &w_);
  t_ = t_s;
}

Eigen::Isometry3d TumblingBody::pose(double t_s) {
  advance_to(t_s);
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.linear() = q_.toRotationMatrix();
  p.translation() = pose0_.translation() + v_ * t_s;
  return p;
}

Eigen::Vector3d TumblingBody::body_rates(double t_s) {
  advance_to(t_s);
  return w_;
}

}  // namespace ephor::rambo
