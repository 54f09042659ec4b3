#include "common/motion/arm_collision_checker.h"

#include <spdlog/fmt/fmt.h>
#include <cmath>

#include "common/arm/arm_workcell.h"

namespace ephor::arm {

namespace {}  // namespace

ArmCollisionChecker::ArmCollisionChecker(const Puma560& arm, const geometry::Workcell& cell,
                                         CollisionConfig config)
    : arm_(arm), cell_(cell), config_(config) {}

std::optional<std::string> ArmCollisionChecker::collision(const Joints& q,
                                                          double min_tip_z_mm) const {
  if (!q.allFinite()) return "joint vector is not finite";
  const auto frames = arm_.link_frames(q);
  const auto in_field = [&](const Eigen::Vector3d& p) { return base_point_to_field(cell_, p); };
  const Eigen::Vector3d shoulder = in_field(frames[1].translation());
  const Eigen::Vector3d elbow = in_field(frames[2].translation());
  const Eigen::Vector3d forearm_start = in_field(frames[3].translation());
  const Eigen::Vector3d wrist = in_field(frames[4].translation());
  const Eigen::Vector3d tip = in_field(arm_.forward(q).translation());

  // Points along each link centre line against the pedestal cylinder.
  const double keep_out = cell_.pedestal_radius_mm + config_.pedestal_clearance_mm;
  auto hits_pedestal = [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b, double skip_mm) {
    const double len = (b - a).norm();
    const int n = std::max(1, static_cast<int>(std::ceil(len / 10.0)));
    for (int i = 0; i <= n; ++i) {
      const double s = len * i / n;
      if (s < skip_mm) continue;
      const Eigen::Vector3d p = a + (b - a) * (i / static_cast<double>(n));
      const double r = std::hypot(p.x() - cell_.base_x_mm, p.y() - cell_.base_y_mm);
      // The top of the pedestal is the shoulder housing, up to base_z.
      if (p.z() < cell_.base_z_mm && r < keep_out) return true;
    }
    return false;
  };
  if (hits_pedestal(shoulder, elbow, config_.shoulder_housing_mm))
    return fmt::format("upper arm inside the pedestal (keep-out radius {:.1f} mm, top z {:.1f} mm)",
                       keep_out, cell_.base_z_mm);
  if (hits_pedestal(elbow, forearm_start, 0.0) || hits_pedestal(forearm_start, wrist, 0.0) ||
      hits_pedestal(wrist, tip, 0.0))
    return fmt::format(
        "forearm or tool inside the pedestal (keep-out radius {:.1f} mm, top z {:.1f} mm)",
        keep_out, cell_.base_z_mm);
  if (tip.z() < config_.tip_table_clearance_mm)
    return fmt::format("tool tip {:.1f} mm above the table (< {:.1f})", tip.z(),
                       config_.tip_table_clearance_mm);
  if (tip.z() < min_tip_z_mm)
    return fmt::format(
        "tool tip at z {:.1f} mm, below the lowest allowed {:.1f} mm for this motion", tip.z(),
        min_tip_z_mm);
  for (const Eigen::Vector3d* p : {&elbow, &forearm_start, &wrist}) {
    if (p->z() < config_.link_table_clearance_mm)
      return fmt::format("arm link {:.1f} mm above the table (< {:.1f})", p->z(),
                         config_.link_table_clearance_mm);
  }

  return std::nullopt;
}

}  // namespace ephor::arm
