#include "common/stripe/stripe_world.h"

#include <numbers>
#include <random>

namespace ephor::stripe {

namespace {

Eigen::Isometry3d perturb(const Eigen::Isometry3d& pose, std::mt19937_64& rng, double mm,
                          double deg) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  Eigen::Vector3d axis(unit(rng), unit(rng), unit(rng));
  if (axis.norm() < 1e-6) axis = Eigen::Vector3d::UnitZ();
  const double angle = deg * std::numbers::pi / 180.0 * unit(rng);
  Eigen::Isometry3d out = pose;
  out.linear() = pose.linear() * Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
  out.translation() += Eigen::Vector3d(mm * unit(rng), mm * unit(rng), mm * unit(rng));
  return out;
}

}  // namespace

RobotTruth RobotTruth::ideal() {
  return RobotTruth{TrueArm::nominal(), SensorCalibration::drawing_cage()};
}

RobotTruth RobotTruth::draw(std::uint64_t seed, double cage_mm, double cage_deg) {
  RobotTruth t{TrueArm(ArmErrors::draw(seed)), SensorCalibration::drawing_cage()};
  std::mt19937_64 rng(seed ^ 0x5eedca9eULL);
  t.cage.camera_in_flange = perturb(t.cage.camera_in_flange, rng, cage_mm, cage_deg);
  t.cage.projector_in_flange = perturb(t.cage.projector_in_flange, rng, cage_mm, cage_deg);
  return t;
}

StripeWorld::StripeWorld(const StripeScene& scene, StripeWorkcell cell, RobotTruth truth,
                         StripeRendererOptions options)
    : scene_(&scene),
      cell_(cell),
      truth_(std::move(truth)),
      renderer_(scene, truth_.cage.camera, options) {}

Eigen::Isometry3d StripeWorld::flange_in_table(const arm::Joints& q) const {
  return cell_.base_in_table * truth_.arm.flange(q);
}

cv::Mat StripeWorld::image(const arm::Joints& q, std::uint64_t seed) const {
  const Eigen::Isometry3d t = flange_in_table(q);
  return renderer_.render(t * truth_.cage.camera_in_flange, t * truth_.cage.projector_in_flange,
                          seed);
}

cv::Mat StripeWorld::spot_image(const arm::Joints& q, std::uint64_t seed) const {
  return renderer_.render_ambient(flange_in_table(q) * truth_.cage.camera_in_flange, seed);
}

}  // namespace ephor::stripe
