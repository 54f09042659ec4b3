#include "common/shepherd/sim/simulator.h"

#include <cmath>
#include <stdexcept>

#include "common/arm/arm_workcell.h"

namespace ephor::sim {
namespace {

constexpr double kTrunkRadiusMm = 70.0;
constexpr double kUpperArmRadiusMm = 60.0;
constexpr double kForearmRadiusMm = 45.0;
constexpr double kWristRadiusMm = 40.0;
constexpr double kToolRadiusMm = 8.0;

}  // namespace

std::vector<ArmPart> arm_parts(const arm::Puma560& puma, const geometry::Workcell& cell,
                               const arm::Joints& q) {
  const auto frames = puma.link_frames(q);
  const auto at = [&](const Eigen::Vector3d& p_base) -> Eigen::Vector3d {
    return arm::base_point_to_field(cell, p_base);
  };
  const Eigen::Vector3d o1 = frames[1].translation();
  const Eigen::Vector3d o2 = frames[2].translation();
  const Eigen::Vector3d z2 = frames[2].linear().col(2);
  const Eigen::Vector3d o3 = frames[3].translation();
  const Eigen::Vector3d wrist = frames[4].translation();  // frames 4, 5, 6 share this origin
  const Eigen::Vector3d z6 = frames[6].linear().col(2);
  const Eigen::Vector3d tip = puma.forward(q).translation();
  // Standard DH puts the shoulder offset d3 on the elbow axis (frame 3); the
  // upper arm physically runs beside the column, offset by d3 along z2.
  const Eigen::Vector3d offset = arm::Puma560::kD3Mm * z2;
  const Eigen::Vector3d flange_housing = wrist + 0.5 * puma.tool_length_mm() * z6;
  return {
      {Eigen::Vector3d(cell.base_x_mm, cell.base_y_mm, 0.0), at(o1), cell.pedestal_radius_mm},
      {at(o1), at(o1 + offset), kTrunkRadiusMm},
      {at(o1 + offset), at(o2 + offset), kUpperArmRadiusMm},
      {at(o2 + offset), at(o3), kUpperArmRadiusMm},
      {at(o3), at(wrist), kForearmRadiusMm},
      {at(wrist), at(flange_housing), kWristRadiusMm},
      {at(flange_housing), at(tip), kToolRadiusMm},
  };
}

Simulator::Simulator(SimulatorConfig config)
    : config_(std::move(config)),
      puma_(arm::make_puma(config_.world.workcell)),
      world_(config_.world),
      servo_(puma_.limits(), arm::park_joints(config_.world.workcell)),
      camera_(config_.camera, config_.world),
      clouds_(config_.clouds, camera_.width(), camera_.height()) {
  if (!std::isfinite(config_.servo_step_s) || config_.servo_step_s <= 0.0 ||
      config_.servo_step_s > 0.01)
    throw std::invalid_argument("sim config: servo_step_s must be in (0, 0.01] s");
  set_world_tool();
}

void Simulator::set_world_tool() {
  const arm::ToolInField tool = arm::tool_in_field(config_.world.workcell, servo_.state().q);
  world_.set_tool_tip(tool.tip_mm, tool.theta_rad);
}

Eigen::Vector3d Simulator::tool_tip_mm() const {
  return arm::tool_in_field(config_.world.workcell, servo_.state().q).tip_mm;
}

void Simulator::step(double dt_s) {
  if (!std::isfinite(dt_s) || dt_s <= 0.0)
    throw std::invalid_argument("Simulator::step: dt must be finite and > 0");
  const int n = static_cast<int>(std::ceil(dt_s / config_.servo_step_s - 1e-9));
  const double h = dt_s / n;
  for (int i = 0; i < n; ++i) {
    servo_.step(h);
    set_world_tool();
    world_.step(h);
  }
}

Scene Simulator::scene() const {
  Scene s;
  s.time_s = world_.time_s();
  s.sheep = world_.sheep();
  if (config_.arm_in_image) s.arm = arm_parts(puma_, config_.world.workcell, servo_.state().q);
  s.clouds = clouds_.at(s.time_s);
  s.escapes = world_.escapes();
  s.saves = world_.saves();
  if (tool_light_on_) {
    ToolLight light;
    light.tip_mm = tool_tip_mm();
    s.tool_light = light;
  }
  return s;
}

namespace {

GroundTruth combine(const Scene& scene, const std::vector<MarkView>& views) {
  GroundTruth gt;
  gt.time_s = scene.time_s;
  gt.escapes = scene.escapes;
  gt.saves = scene.saves;
  for (size_t i = 0; i < scene.sheep.size(); ++i) gt.sheep.push_back({scene.sheep[i], views[i]});
  return gt;
}

}  // namespace

GroundTruth Simulator::truth() const {
  const Scene s = scene();
  return combine(s, camera_.mark_views(s.sheep, s.arm));
}

GroundTruth Simulator::render(std::vector<uint8_t>& image) {
  return render(scene(), camera_, image);
}

GroundTruth Simulator::render(const Scene& scene, CameraRenderer& camera,
                              std::vector<uint8_t>& image) {
  return combine(scene,
                 camera.render(scene.sheep, scene.arm, image,
                               scene.tool_light ? &*scene.tool_light : nullptr, scene.clouds));
}

}  // namespace ephor::sim
