#include "common/stripe/sensor_model.h"

#include <cmath>
#include <stdexcept>

namespace ephor::stripe {

CameraIntrinsics CameraIntrinsics::paper_camera() { return CameraIntrinsics{}; }

Eigen::Matrix4d CameraIntrinsics::projection_matrix() const {
  Eigen::Matrix4d p;
  p << fx_px, 0.0, cx_px, 0.0,  //
      0.0, fy_px, cy_px, 0.0,   //
      0.0, 0.0, 0.0, 1.0,       //
      0.0, 0.0, 1.0, 0.0;
  return p;
}

Eigen::Matrix4d CameraIntrinsics::inverse_projection_matrix() const {
  Eigen::Matrix4d q;
  q << 1.0 / fx_px, 0.0, 0.0, -cx_px / fx_px,  //
      0.0, 1.0 / fy_px, 0.0, -cy_px / fy_px,   //
      0.0, 0.0, 0.0, 1.0,                      //
      0.0, 0.0, 1.0, 0.0;
  return q;
}

Eigen::Vector2d CameraIntrinsics::project(const Eigen::Vector3d& p) const {
  return {fx_px * p.x() / p.z() + cx_px, fy_px * p.y() / p.z() + cy_px};
}

Eigen::Vector3d CameraIntrinsics::ray(double u, double v) const {
  return Eigen::Vector3d((u - cx_px) / fx_px, (v - cy_px) / fy_px, 1.0).normalized();
}

bool CameraIntrinsics::valid() const {
  return width_px > 0 && height_px > 0 && std::isfinite(fx_px) && std::isfinite(fy_px) &&
         fx_px > 0.0 && fy_px > 0.0 && std::isfinite(cx_px) && std::isfinite(cy_px);
}

Eigen::Isometry3d look_at(const Eigen::Vector3d& eye, const Eigen::Vector3d& target,
                          const Eigen::Vector3d& up_hint) {
  const Eigen::Vector3d z = (target - eye).normalized();
  Eigen::Vector3d y = up_hint - up_hint.dot(z) * z;
  if (y.norm() < 1e-9) throw std::invalid_argument("look_at: up hint parallel to the view");
  y.normalize();
  const Eigen::Vector3d x = y.cross(z);
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear().col(0) = x;
  t.linear().col(1) = y;
  t.linear().col(2) = z;
  t.translation() = eye;
  return t;
}

SensorCalibration SensorCalibration::drawing_cage() {
  SensorCalibration s;
  s.projector_in_flange = Eigen::Isometry3d::Identity();
  s.projector_in_flange.translation() = Eigen::Vector3d(0.0, 0.0, 80.0);
  s.camera_in_flange = look_at(Eigen::Vector3d(120.0, 0.0, 60.0), Eigen::Vector3d(0.0, 0.0, 380.0),
                               Eigen::Vector3d(0.0, 1.0, 0.0));
  s.camera = CameraIntrinsics::paper_camera();
  return s;
}

}  // namespace ephor::stripe
