#include "procs/stripe/planner/raster_plan.h"

#include <cmath>
#include <numbers>
#include <optional>
#include <sstream>

#include <spdlog/fmt/fmt.h>

#include "common/arm/arm_workcell.h"
#include "common/motion/arm_collision_checker.h"

namespace ephor::stripe {

namespace {

// Joint readings for the projector at `pose`, or why not.
std::optional<arm::Joints> reach(const Eigen::Isometry3d& pose, const StripeWorkcell& cell,
                                 const arm::ArmCollisionChecker& collisions, const TrueArm& model,
                                 const SensorCalibration& calibration, const arm::Joints& near,
                                 std::string* why) {
  const auto q = cell.joints_for(flange_for_projector(pose, calibration), near,
                                 model.errors().zero_offset_rad);
  if (!q) {
    const Eigen::Vector3d flange_in_base =
        cell.base_in_table.inverse() * flange_for_projector(pose, calibration).translation();
    *why = fmt::format(
        "the PUMA 560 cannot put the projector there within its joint limits (flange {:.0f} mm "
        "from the shoulder, {:.0f} mm from the column)",
        flange_in_base.norm(), flange_in_base.head<2>().norm());
    return std::nullopt;
  }
  if (const auto hit = collisions.collision(*q)) {
    *why = "the arm would collide: " + *hit;
    return std::nullopt;
  }
  return q;
}

}  // namespace

void parse_region(const std::string& text, RasterSpec& spec) {
  std::vector<double> v;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    try {
      size_t used = 0;
      const double x = std::stod(item, &used);
      if (used != item.size()) throw std::invalid_argument(item);
      v.push_back(x);
    } catch (const std::exception&) {
      throw PlanError("--region \"" + text + "\": \"" + item +
                      "\" is not a number (want X0,Y0,X1,Y1 in mm)");
    }
  }
  if (v.size() != 4)
    throw PlanError("--region \"" + text + "\": want four numbers X0,Y0,X1,Y1 (mm), got " +
                    std::to_string(v.size()));
  for (double x : v)
    if (!std::isfinite(x)) throw PlanError("--region \"" + text + "\": numbers must be finite");
  if (!(v[2] > v[0]) || !(v[3] > v[1]))
    throw PlanError("--region \"" + text + "\": want X1 > X0 and Y1 > Y0");
  spec.x0_mm = v[0];
  spec.y0_mm = v[1];
  spec.x1_mm = v[2];
  spec.y1_mm = v[3];
}

RasterPlan plan_raster(const RasterSpec& spec, const geometry::Workcell& workcell,
                       const TrueArm& model, const SensorCalibration& calibration,
                       const arm::Joints& start) {
  if (!(spec.step_mm > 0.0) || !std::isfinite(spec.step_mm))
    throw PlanError(fmt::format("step {} mm: must be > 0", spec.step_mm));
  if (!(spec.height_mm > 0.0) || !std::isfinite(spec.height_mm))
    throw PlanError(fmt::format("scan height {} mm: must be > 0", spec.height_mm));
  const StripeWorkcell cell = StripeWorkcell::from_workcell(workcell);
  const arm::Puma560 puma = arm::make_puma(workcell);
  const arm::ArmCollisionChecker collisions(puma, workcell);
  const double azimuth = spec.stripes_along_y ? std::numbers::pi / 2 : 0.0;
  // The corners first: the user's region, named as given.
  const struct {
    const char* name;
    double x, y;
  } corners[] = {{"(x0, y0)", spec.x0_mm, spec.y0_mm},
                 {"(x1, y0)", spec.x1_mm, spec.y0_mm},
                 {"(x0, y1)", spec.x0_mm, spec.y1_mm},
                 {"(x1, y1)", spec.x1_mm, spec.y1_mm}};
  for (const auto& c : corners) {
    std::string why;
    if (!reach(projector_looking_down(c.x, c.y, spec.height_mm, azimuth), cell, collisions, model,
               calibration, start, &why))
      throw PlanError(fmt::format(
          "region corner {} = ({:g}, {:g}) mm is out of reach with the projector {:g} mm above "
          "the table: {}",
          c.name, c.x, c.y, spec.height_mm, why));
  }
  RasterPlan plan;
  plan.spec = spec;
  try {
    plan.projector_poses = raster_projector_poses(spec);
  } catch (const std::invalid_argument& e) {
    throw PlanError(e.what());
  }
  arm::Joints q = start;
  for (size_t i = 0; i < plan.projector_poses.size(); ++i) {
    std::string why;
    const auto next = reach(plan.projector_poses[i], cell, collisions, model, calibration, q, &why);
    const Eigen::Vector3d p = plan.projector_poses[i].translation();
    if (!next)
      throw PlanError(fmt::format("stripe {} at ({:.0f}, {:.0f}) mm is out of reach: {}", i, p.x(),
                                  p.y(), why));
    q = *next;
    plan.goals.push_back(q);
  }
  return plan;
}

}  // namespace ephor::stripe
