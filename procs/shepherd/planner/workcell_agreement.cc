#include "procs/shepherd/planner/workcell_agreement.h"

#include <cmath>

#include <fmt/format.h>

namespace ephor::planner {

WorkcellAgreement::WorkcellAgreement(const geometry::Workcell& cell, double tolerance_mm)
    : cell_(cell), tolerance_mm_(tolerance_mm) {}

std::optional<std::string> WorkcellAgreement::update(std::optional<Plane> plane, double tip_z_mm) {
  // Moving, or no motion completed yet, or a non-finite report: no evidence.
  if (!plane || !std::isfinite(tip_z_mm)) return std::nullopt;
  const bool object = *plane == Plane::kObject;
  const double expected = object ? cell_.object_plane_z_mm : cell_.elevation_plane_z_mm;
  const bool now_agrees = std::abs(tip_z_mm - expected) <= tolerance_mm_;
  if (now_agrees == agrees_) return std::nullopt;
  agrees_ = now_agrees;
  const char* name = object ? "object" : "elevation";
  if (!now_agrees) {
    return fmt::format(
        "work cell disagreement: ARM_STATE has the tool at rest on the {} plane at z = {:.1f} mm, "
        "this planner's work cell puts that plane at z = {:.1f} mm. The arm and the planner were "
        "given different work cells (--workcell of each in the manifest); not planning until "
        "they agree",
        name, tip_z_mm, expected);
  }
  return fmt::format(
      "work cell agreement: ARM_STATE has the tool on the {} plane at z = {:.1f} mm as expected; "
      "planning again",
      name, tip_z_mm);
}

std::string calibration_disagreement(const geometry::Workcell& cell, double calibration_object_z_mm,
                                     double calibration_elevation_z_mm) {
  constexpr double kToleranceMm = 1.0;
  std::string why;
  auto check = [&](const char* name, double calibration_z, double cell_z) {
    if (std::abs(calibration_z - cell_z) <= kToleranceMm) return;
    if (!why.empty()) why += "; ";
    why +=
        fmt::format("the calibration's {} plane is at z = {:.1f} mm, the work cell's at {:.1f} mm",
                    name, calibration_z, cell_z);
  };
  check("object", calibration_object_z_mm, cell.object_plane_z_mm);
  check("elevation", calibration_elevation_z_mm, cell.elevation_plane_z_mm);
  return why;
}

}  // namespace ephor::planner
