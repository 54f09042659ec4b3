#include "common/stripe/calibration_file.h"

#include <cmath>
#include <fstream>
#include <numbers>

#include <google/protobuf/text_format.h>

#include "common/config/repo_paths.h"
#include "common/config/text_proto.h"
#include "common/stripe/stripe_calibration.pb.h"

namespace ephor::stripe {

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

Eigen::Isometry3d load_pose(const TextProto& text, bool has, const config::StripePose& p,
                            const std::string& name) {
  if (!has) text.fail(name, "missing (required)");
  if (p.translation_mm_size() != 3)
    text.fail(name + ".translation_mm",
              "needs 3 values (x, y, z mm), has " + std::to_string(p.translation_mm_size()));
  if (p.quaternion_wxyz_size() != 4)
    text.fail(name + ".quaternion_wxyz",
              "needs 4 values (w, x, y, z), has " + std::to_string(p.quaternion_wxyz_size()));
  for (int i = 0; i < 3; ++i)
    if (!std::isfinite(p.translation_mm(i)))
      text.fail(name + ".translation_mm[" + std::to_string(i) + "]", "must be a finite number");
  for (int i = 0; i < 4; ++i)
    if (!std::isfinite(p.quaternion_wxyz(i)))
      text.fail(name + ".quaternion_wxyz[" + std::to_string(i) + "]", "must be a finite number");
  Eigen::Quaterniond q(p.quaternion_wxyz(0), p.quaternion_wxyz(1), p.quaternion_wxyz(2),
                       p.quaternion_wxyz(3));
  if (std::abs(q.norm() - 1.0) > 1e-6)
    text.fail(name + ".quaternion_wxyz",
              "is not a unit quaternion (norm " + std::to_string(q.norm()) + ")");
  q.normalize();
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  out.linear() = q.toRotationMatrix();
  out.translation() =
      Eigen::Vector3d(p.translation_mm(0), p.translation_mm(1), p.translation_mm(2));
  return out;
}

void save_pose(const Eigen::Isometry3d& pose, config::StripePose* p) {
  for (int i = 0; i < 3; ++i) p->add_translation_mm(pose.translation()[i]);
  Eigen::Quaterniond q(pose.linear());
  q.normalize();
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();
  p->add_quaternion_wxyz(q.w());
  p->add_quaternion_wxyz(q.x());
  p->add_quaternion_wxyz(q.y());
  p->add_quaternion_wxyz(q.z());
}

}  // namespace

StripeCalibration StripeCalibration::drawing(std::int64_t robot_seed) {
  StripeCalibration c;
  c.robot_seed = robot_seed;
  c.measured = "the nominal arm and the cage from the mechanical drawings (not measured)";
  return c;
}

StripeCalibration load_stripe_calibration(const std::string& path) {
  config::StripeCalibrationFile file;
  const TextProto text(path, &file);
  StripeCalibration c;
  if (!file.has_robot_seed())
    text.fail("robot_seed", "missing (required: the robot it was measured on)");
  c.robot_seed = file.robot_seed();
  if (file.zero_offset_deg_size() != 6)
    text.fail("zero_offset_deg", file.zero_offset_deg_size() == 0
                                     ? std::string("missing (required: joints 1-6, degrees)")
                                     : "needs 6 values (joints 1-6), has " +
                                           std::to_string(file.zero_offset_deg_size()));
  for (int j = 0; j < 6; ++j) {
    const double v = file.zero_offset_deg(j);
    if (!std::isfinite(v) || std::abs(v) > 30.0)
      text.fail("zero_offset_deg[" + std::to_string(j) + "]",
                "must be a finite number within +-30 deg, is " + std::to_string(v));
    c.arm.zero_offset_rad[j] = v * kDeg;
  }
  if (file.link_error_size() != 0 && file.link_error_size() != 6)
    text.fail("link_error",
              "needs 6 entries (links 1-6) or none, has " + std::to_string(file.link_error_size()));
  for (int j = 0; j < file.link_error_size(); ++j) {
    const auto& l = file.link_error(j);
    const std::string name = "link_error[" + std::to_string(j) + "]";
    if (!l.has_d_mm() || !l.has_a_mm() || !l.has_alpha_deg())
      text.fail(name, "needs d_mm, a_mm and alpha_deg");
    if (!std::isfinite(l.d_mm()) || !std::isfinite(l.a_mm()) || !std::isfinite(l.alpha_deg()) ||
        std::abs(l.d_mm()) > 50.0 || std::abs(l.a_mm()) > 50.0 || std::abs(l.alpha_deg()) > 10.0)
      text.fail(name, "must be finite and small (|d|, |a| <= 50 mm, |alpha| <= 10 deg)");
    c.arm.dh_error[static_cast<size_t>(j)] = arm::DhLink{l.d_mm(), l.a_mm(), l.alpha_deg() * kDeg};
  }
  c.sensor.camera_in_flange =
      load_pose(text, file.has_camera_in_flange(), file.camera_in_flange(), "camera_in_flange");
  c.sensor.projector_in_flange = load_pose(text, file.has_projector_in_flange(),
                                           file.projector_in_flange(), "projector_in_flange");
  if (!file.has_camera()) text.fail("camera", "missing (required: the camera's projection P)");
  const auto& k = file.camera();
  auto need = [&](bool has, const char* field) {
    if (!has) text.fail(std::string("camera.") + field, "missing (required)");
  };
  need(k.has_width_px(), "width_px");
  need(k.has_height_px(), "height_px");
  need(k.has_fx_px(), "fx_px");
  need(k.has_fy_px(), "fy_px");
  need(k.has_cx_px(), "cx_px");
  need(k.has_cy_px(), "cy_px");
  c.sensor.camera.width_px = k.width_px();
  c.sensor.camera.height_px = k.height_px();
  c.sensor.camera.fx_px = k.fx_px();
  c.sensor.camera.fy_px = k.fy_px();
  c.sensor.camera.cx_px = k.cx_px();
  c.sensor.camera.cy_px = k.cy_px();
  if (!c.sensor.camera.valid())
    text.fail("camera", "is not a valid camera (sizes >= 1, focal lengths > 0, finite)");
  c.measured = file.measured();
  c.report.assign(file.report().begin(), file.report().end());
  return c;
}

void check_calibration_robot(const StripeCalibration& calibration, std::int64_t robot_seed,
                             const std::string& path) {
  if (calibration.robot_seed != robot_seed)
    throw ConfigError(path + ": measured on robot seed " + std::to_string(calibration.robot_seed) +
                      ", this robot is seed " + std::to_string(robot_seed) +
                      " (calibrate it: tools/ephor stripe calibrate --robot-seed " +
                      std::to_string(robot_seed) + ")");
}

StripeCalibration calibration_from_flags(const std::string& path, std::int64_t robot_seed) {
  if (path.empty()) return StripeCalibration::drawing(robot_seed);
  const StripeCalibration c = load_stripe_calibration(resolve_repo_path(path));
  check_calibration_robot(c, robot_seed, path);
  return c;
}

std::string stripe_calibration_text(const StripeCalibration& c) {
  config::StripeCalibrationFile file;
  file.set_robot_seed(c.robot_seed);
  for (int j = 0; j < 6; ++j) file.add_zero_offset_deg(c.arm.zero_offset_rad[j] / kDeg);
  bool links = false;
  for (const auto& l : c.arm.dh_error)
    links = links || l.d_mm != 0.0 || l.a_mm != 0.0 || l.alpha_rad != 0.0;
  if (links)
    for (const auto& l : c.arm.dh_error) {
      auto* e = file.add_link_error();
      e->set_d_mm(l.d_mm);
      e->set_a_mm(l.a_mm);
      e->set_alpha_deg(l.alpha_rad / kDeg);
    }
  save_pose(c.sensor.camera_in_flange, file.mutable_camera_in_flange());
  save_pose(c.sensor.projector_in_flange, file.mutable_projector_in_flange());
  auto* k = file.mutable_camera();
  k->set_width_px(c.sensor.camera.width_px);
  k->set_height_px(c.sensor.camera.height_px);
  k->set_fx_px(c.sensor.camera.fx_px);
  k->set_fy_px(c.sensor.camera.fy_px);
  k->set_cx_px(c.sensor.camera.cx_px);
  k->set_cy_px(c.sensor.camera.cy_px);
  file.set_measured(c.measured);
  for (const auto& r : c.report) file.add_report(r);
  std::string body;
  google::protobuf::TextFormat::Printer printer;
  printer.PrintToString(file, &body);
  return "# The light-stripe sensor's calibration (common/stripe/stripe_calibration.proto):\n"
         "# zero references and links of the arm, C_T, S_T and P. mm and degrees.\n" +
         body;
}

void save_stripe_calibration(const std::string& path, const StripeCalibration& calibration) {
  std::ofstream out(path);
  out << stripe_calibration_text(calibration);
  out.close();
  if (!out) throw ConfigError("calibration file " + path + ": cannot be written");
}

}  // namespace ephor::stripe
