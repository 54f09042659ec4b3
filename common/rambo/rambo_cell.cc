#include "common/rambo/rambo_cell.h"

#include <cmath>
#include <random>
#include <stdexcept>

namespace ephor::rambo {
namespace {

constexpr double kSx = 240.0, kSy = 180.0, kSz = 140.0;  // box, mm

// Tool pose with its z along `beam` (unit) and the tip at `tip`; x chosen
// level with the target's x-y plane where it can be.
Eigen::Isometry3d beam_pose(const Eigen::Vector3d& tip, const Eigen::Vector3d& beam) {
  Eigen::Vector3d x = Eigen::Vector3d::UnitZ().cross(beam);
  if (x.norm() < 1e-6) x = Eigen::Vector3d::UnitY().cross(beam);
  x.normalize();
  const Eigen::Vector3d y = beam.cross(x);
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.linear().col(0) = x;
  p.linear().col(1) = y;
  p.linear().col(2) = beam;
  p.translation() = tip;
  return p;
}

}  // namespace

TargetSpec RamboCell::builtin_target() {
  TargetSpec t;
  // Lenses on the faces that start turned towards the arm (-x), tubes tilted
  // towards it (within 27 deg of -x) so that a goal 200 mm out stays within
  // the PUMA's reach while the tumble turns the target (why: target.pbtxt).
  t.diodes = {
      {"front", {-kSx / 2, 20.0, 10.0}, Eigen::Vector3d(-1.0, 0.0, 0.0), kStandoffMm},
      {"top", {-40.0, -20.0, kSz / 2}, Eigen::Vector3d(-2.0, 0.0, 1.0).normalized(), kStandoffMm},
      {"right", {-30.0, -kSy / 2, 0.0}, Eigen::Vector3d(-2.0, -1.0, 0.0).normalized(), kStandoffMm},
      {"left", {-50.0, kSy / 2, -10.0}, Eigen::Vector3d(-2.0, 1.0, 0.0).normalized(), kStandoffMm},
  };
  // The box's cut corner turned (180 deg about z) to (-x, -y, +z), towards
  // the arm: a box shows the same image in two poses 180 deg apart unless
  // the cut is in view, and pose estimation must not lock onto the wrong one.
  const TargetModel box = TargetModel::truncated_box(kSx, kSy, kSz, {60.0, 50.0, 40.0});
  for (const Eigen::Vector3d& v : box.vertices()) t.vertices_mm.emplace_back(-v.x(), -v.y(), v.z());
  t.faces = box.faces();
  t.principal_moments_mm2 =
      Eigen::Vector3d(kSy * kSy + kSz * kSz, kSx * kSx + kSz * kSz, kSx * kSx + kSy * kSy) / 12.0;
  return t;
}

RamboCell RamboCell::make(int diode_count) {
  if (diode_count < 1 || diode_count > 4)
    throw std::invalid_argument("diode count " + std::to_string(diode_count) +
                                " is outside 1-4 (the built-in target carries four diodes)");
  return make(builtin_target(), diode_count);
}

RamboCell RamboCell::make(const TargetSpec& target, int diode_count) {
  const int available = static_cast<int>(target.diodes.size());
  if (diode_count < 1 || diode_count > available)
    throw std::invalid_argument("diode count " + std::to_string(diode_count) + " is outside 1-" +
                                std::to_string(available) + " (the target model carries " +
                                std::to_string(available) + ")");
  std::vector<Diode> diodes(target.diodes.begin(), target.diodes.begin() + diode_count);
  std::vector<GoalPoint> goals;
  for (const Diode& d : diodes) {
    GoalPoint g;
    g.name = d.name;
    g.in_target = beam_pose(d.lens_mm + d.standoff_mm * d.axis, -d.axis);
    goals.push_back(g);
  }
  RamboCell c{TargetModel(target.vertices_mm, target.faces, goals), diodes,
              target.principal_moments_mm2, CameraIntrinsics{}};
  c.camera.fx_px = c.camera.fy_px = 380.0;  // 80 deg across 640 px: the whole target at 200 mm
  // The camera 60 mm beside the laser on the tool plate, looking along the beam.
  c.camera_in_tool.translation() = Eigen::Vector3d(0.0, -60.0, -40.0);
  // Start: the tool 360 mm from the target's centre, aimed at it from above
  // and aside, so that the beam is on no diode (22 deg and 57 mm off the
  // front one) until the planner moves it there.
  const arm::Puma560 arm(c.tool_length_mm);
  const Eigen::Vector3d start_tip(560.0, -100.0, 200.0);
  const auto q = arm.nearest_inverse(
      beam_pose(start_tip, (Eigen::Vector3d(900.0, 0.0, 100.0) - start_tip).normalized()),
      arm::Joints::Zero());
  if (!q) throw std::logic_error("RamboCell: the start pose is out of the PUMA's reach");
  c.start_joints = *q;
  return c;
}

TumblingMotion RamboCell::draw_motion(std::uint64_t seed, double spin_deg_s,
                                      double drift_mm_s) const {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n(0.0, 1.0);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  TumblingMotion m;
  // A small initial tilt (up to 10 deg) so no face starts square to the camera.
  const Eigen::Vector3d tilt_axis = Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized();
  m.pose0.linear() = Eigen::AngleAxisd(u(rng) * 10.0 * M_PI / 180.0, tilt_axis).toRotationMatrix();
  m.pose0.translation() = Eigen::Vector3d(900.0, 0.0, 100.0);
  m.velocity_mm_s = Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized() * drift_mm_s * u(rng);
  m.body_rates_rad_s =
      Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized() * spin_deg_s * M_PI / 180.0;
  return m;
}

Eigen::Isometry3d RamboCell::goal_in_target(int i) const {
  return model.goals().at(static_cast<std::size_t>(i)).in_target;
}

}  // namespace ephor::rambo
