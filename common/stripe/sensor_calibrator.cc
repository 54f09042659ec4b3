#include "common/stripe/sensor_calibrator.h"

#include <cmath>
#include <numbers>

#include <opencv2/imgproc.hpp>

#include "common/stripe/plane_fit.h"

namespace ephor::stripe {

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

arm::Joints reach(const StripeWorkcell& cell, const TrueArm& model, const Eigen::Isometry3d& flange,
                  const arm::Joints& near, const char* what) {
  const auto q = cell.joints_for(flange, near, model.errors().zero_offset_rad);
  if (!q)
    throw CalibrationError(std::string(what) + ": pose out of reach at (" +
                           std::to_string(flange.translation().x()) + ", " +
                           std::to_string(flange.translation().y()) + ", " +
                           std::to_string(flange.translation().z()) + ") mm");
  return *q;
}

}  // namespace

std::optional<Eigen::Vector2d> find_spot(const cv::Mat& image, int threshold) {
  if (image.empty() || image.type() != CV_8UC1) return std::nullopt;
  cv::Mat dark = image < threshold;
  cv::Mat labels, stats, centroids;
  const int n = cv::connectedComponentsWithStats(dark, labels, stats, centroids, 8, CV_32S);
  int best = -1;
  for (int i = 1; i < n; ++i)
    if (best < 0 || stats.at<int>(i, cv::CC_STAT_AREA) > stats.at<int>(best, cv::CC_STAT_AREA))
      best = i;
  if (best < 0) return std::nullopt;
  const int x = stats.at<int>(best, cv::CC_STAT_LEFT), y = stats.at<int>(best, cv::CC_STAT_TOP);
  const int w = stats.at<int>(best, cv::CC_STAT_WIDTH), h = stats.at<int>(best, cv::CC_STAT_HEIGHT);
  if (x <= 0 || y <= 0 || x + w >= image.cols || y + h >= image.rows) return std::nullopt;
  // Darkness-weighted centroid over the blob's box grown by 2 px, so the
  // anti-aliased edge counts by how much of the spot each pixel covers.
  const double bright = 170.0;
  double sw = 0, su = 0, sv = 0;
  for (int v = std::max(0, y - 2); v < std::min(image.rows, y + h + 2); ++v)
    for (int u = std::max(0, x - 2); u < std::min(image.cols, x + w + 2); ++u) {
      const double wgt = std::max(0.0, bright - image.at<unsigned char>(v, u));
      sw += wgt;
      su += wgt * u;
      sv += wgt * v;
    }
  if (!(sw > 0)) return std::nullopt;
  return Eigen::Vector2d(su / sw, sv / sw);
}

CameraAimResult calibrate_camera_aim(CalibrationRig& rig, const StripeWorkcell& cell,
                                     const TrueArm& model, const SensorCalibration& current,
                                     const Eigen::Vector2d& spot_xy_mm, double height_mm,
                                     double raise_mm) {
  const CameraIntrinsics& k = current.camera;
  // Camera straight down, rows along +y of the table.
  Eigen::Isometry3d cam =
      look_at(Eigen::Vector3d(spot_xy_mm.x(), spot_xy_mm.y(), height_mm),
              Eigen::Vector3d(spot_xy_mm.x(), spot_xy_mm.y(), 0.0), Eigen::Vector3d::UnitY());
  arm::Joints q = StripeWorkcell::reference_joints();
  auto spot_at = [&](const Eigen::Isometry3d& c) {
    q = reach(cell, model, c * current.camera_in_flange.inverse(), q, "camera aim");
    const auto s = find_spot(rig.spot_image(q));
    if (!s) throw CalibrationError("camera aim: the spot is not in view");
    return Eigen::Vector2d(s->x() - k.cx_px, s->y() - k.cy_px);
  };
  // Centre the spot (the principal ray then passes through it).
  for (int it = 0; it < 5; ++it) {
    const Eigen::Vector2d d = spot_at(cam);
    if (d.norm() < 0.02) break;
    cam.translation() += cam.linear() * Eigen::Vector3d(d.x() * height_mm / k.fx_px,
                                                        d.y() * height_mm / k.fy_px, 0.0);
  }
  const Eigen::Vector2d centred = spot_at(cam);
  Eigen::Isometry3d up = cam;
  up.translation().z() += raise_mm;
  const Eigen::Vector2d moved = spot_at(up) - centred;
  // The table's up direction in the true camera frame: the spot at depth L
  // on the principal ray, seen after rising h, is offset by -h u_perp in
  // camera coordinates at depth L + h.
  const double l = height_mm, h = raise_mm;
  Eigen::Vector3d u(-moved.x() * (l + h) / (k.fx_px * h), -moved.y() * (l + h) / (k.fy_px * h),
                    0.0);
  u.z() = -std::sqrt(std::max(0.0, 1.0 - u.head<2>().squaredNorm()));
  const Eigen::Vector3d believed(0.0, 0.0, -1.0);
  // New C_T rotation R' = R * D with D^T believed = u.
  const Eigen::Matrix3d d = Eigen::Quaterniond::FromTwoVectors(u, believed).toRotationMatrix();
  CameraAimResult r;
  r.updated = current;
  r.updated.camera_in_flange.linear() = current.camera_in_flange.linear() * d;
  r.correction_deg = std::acos(std::clamp(u.dot(believed), -1.0, 1.0)) / kDeg;
  r.spot_shift_px = moved;
  return r;
}

CameraScaleRollResult calibrate_camera_scale_and_roll(CalibrationRig& rig,
                                                      const StripeWorkcell& cell,
                                                      const TrueArm& model,
                                                      const SensorCalibration& current,
                                                      const Eigen::Vector2d& spot_xy_mm,
                                                      double height_mm, double step_mm) {
  const CameraIntrinsics& k = current.camera;
  Eigen::Isometry3d cam =
      look_at(Eigen::Vector3d(spot_xy_mm.x(), spot_xy_mm.y(), height_mm),
              Eigen::Vector3d(spot_xy_mm.x(), spot_xy_mm.y(), 0.0), Eigen::Vector3d::UnitY());
  arm::Joints q = StripeWorkcell::reference_joints();
  auto spot_at = [&](const Eigen::Isometry3d& c) {
    q = reach(cell, model, c * current.camera_in_flange.inverse(), q, "camera scale");
    const auto s = find_spot(rig.spot_image(q));
    if (!s) throw CalibrationError("camera scale: the spot is not in view");
    return Eigen::Vector2d(s->x() - k.cx_px, s->y() - k.cy_px);
  };
  for (int it = 0; it < 5; ++it) {
    const Eigen::Vector2d d = spot_at(cam);
    if (d.norm() < 0.02) break;
    cam.translation() += cam.linear() * Eigen::Vector3d(d.x() * height_mm / k.fx_px,
                                                        d.y() * height_mm / k.fy_px, 0.0);
  }
  // Central differences over +-step along each believed camera axis.
  auto motion = [&](const Eigen::Vector3d& axis_in_camera) {
    Eigen::Isometry3d plus = cam, minus = cam;
    plus.translation() += step_mm * (cam.linear() * axis_in_camera);
    minus.translation() -= step_mm * (cam.linear() * axis_in_camera);
    return Eigen::Vector2d((spot_at(plus) - spot_at(minus)) / 2.0);
  };
  const Eigen::Vector2d dx = motion(Eigen::Vector3d::UnitX());
  const Eigen::Vector2d dy = motion(Eigen::Vector3d::UnitY());
  // If the true camera is the believed one turned by phi about its z, a
  // camera step s along believed x moves the spot by -(f s / Z)(cos phi,
  // -sin phi) in the image, a step along y by -(f s / Z)(sin phi, cos phi).
  const double phi_x = std::atan2(dx.y(), -dx.x());
  const double phi_y = std::atan2(-dy.x(), -dy.y());
  const double phi = 0.5 * (phi_x + phi_y);
  CameraScaleRollResult r;
  r.updated = current;
  r.fx_ratio = dx.norm() * height_mm / (step_mm * k.fx_px);
  r.fy_ratio = dy.norm() * height_mm / (step_mm * k.fy_px);
  r.updated.camera.fx_px = k.fx_px * r.fx_ratio;
  r.updated.camera.fy_px = k.fy_px * r.fy_ratio;
  r.updated.camera_in_flange.linear() =
      current.camera_in_flange.linear() *
      Eigen::AngleAxisd(phi, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  r.roll_correction_deg = phi / kDeg;
  r.x_move_px = dx;
  r.y_move_px = dy;
  return r;
}

ProjectorPlaneResult calibrate_projector_plane(CalibrationRig& rig, const StripeWorkcell& cell,
                                               const TrueArm& model,
                                               const SensorCalibration& current,
                                               const Eigen::Vector2d& centre_xy_mm,
                                               const std::vector<double>& heights_mm) {
  StripeExtractor extractor;
  std::vector<Eigen::Vector3d> in_flange;
  arm::Joints q = StripeWorkcell::reference_joints();
  for (double height : heights_mm) {
    for (double pitch_deg : {0.0, 8.0, -8.0}) {
      const Eigen::Isometry3d s =
          projector_looking_down(centre_xy_mm.x(), centre_xy_mm.y(), height, std::numbers::pi / 2) *
          Eigen::AngleAxisd(pitch_deg * kDeg, Eigen::Vector3d::UnitX());
      q = reach(cell, model, flange_for_projector(s, current), q, "projector calibration");
      const Stripe stripe = extractor.extract(rig.stripe_image(q));
      const Eigen::Isometry3d t = cell.base_in_table * model.flange(rig.readings(q));
      const Eigen::Isometry3d c = t * current.camera_in_flange;
      for (const StripePoint& p : stripe.points) {
        const Eigen::Vector3d d = c.linear() * current.camera.ray(p.u_px, p.row);
        if (!(d.z() < -1e-6)) continue;
        const Eigen::Vector3d on_table = c.translation() - c.translation().z() / d.z() * d;
        in_flange.push_back(t.inverse() * on_table);
      }
    }
  }
  if (in_flange.size() < 100)
    throw CalibrationError("projector calibration: only " + std::to_string(in_flange.size()) +
                           " stripe points seen on the table (need 100)");
  const auto fit = PlaneFit::fit(in_flange);
  if (!fit) throw CalibrationError("projector calibration: the stripe points do not span a plane");
  const Eigen::Isometry3d& old = current.projector_in_flange;
  Eigen::Vector3d x = fit->normal;
  if (x.dot(old.linear().col(0)) < 0.0) x = -x;
  Eigen::Vector3d y = old.linear().col(1) - old.linear().col(1).dot(x) * x;
  y.normalize();
  ProjectorPlaneResult r;
  r.updated = current;
  Eigen::Isometry3d& s = r.updated.projector_in_flange;
  s.linear().col(0) = x;
  s.linear().col(1) = y;
  s.linear().col(2) = x.cross(y);
  const double off = x.dot(old.translation() - fit->centroid);
  s.translation() = old.translation() - off * x;
  r.normal_change_deg = std::acos(std::clamp(x.dot(old.linear().col(0)), -1.0, 1.0)) / kDeg;
  r.offset_change_mm = off;
  r.rms_mm = fit->rms_mm;
  r.points = in_flange.size();
  return r;
}

}  // namespace ephor::stripe
