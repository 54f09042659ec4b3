#include "common/shepherd/calibrate/calibration_plan.h"

#include <cmath>
#include <stdexcept>

#include "common/arm/arm_workcell.h"

namespace ephor::calibrate {

using calibration::Plane;

namespace {

std::string describe(const CalibrationStop& s) {
  char buf[128];
  std::snprintf(buf, sizeof buf, "(%.1f, %.1f, %.1f) mm in the %s plane", s.tip_mm.x(),
                s.tip_mm.y(), s.tip_mm.z(), s.plane == Plane::kObject ? "object" : "elevation");
  return buf;
}

}  // namespace

CalibrationPlan::CalibrationPlan(const geometry::Workcell& cell, CalibrationPlanConfig config) {
  const double in = config.object_inset_mm;
  if (!std::isfinite(in) || in < 0.0 || 2.0 * in >= cell.field_width_mm)
    throw std::invalid_argument("object_inset_mm must be in [0, field width / 2)");
  if (!std::isfinite(config.elevation_half_x_mm) || !std::isfinite(config.elevation_half_y_mm) ||
      config.elevation_half_x_mm <= 0.0 || config.elevation_half_y_mm <= 0.0)
    throw std::invalid_argument("elevation half sizes must be finite and > 0");
  const double cx = cell.centre_x_mm(), cy = cell.centre_y_mm();
  const double ze = cell.elevation_plane_z_mm, zo = cell.object_plane_z_mm;
  const double hx = config.elevation_half_x_mm, hy = config.elevation_half_y_mm;
  // Elevation plane, counter-clockwise from the park corner (lower right).
  for (const auto& [x, y] : {std::pair{cx + hx, cy - hy}, std::pair{cx + hx, cy + hy},
                             std::pair{cx - hx, cy + hy}, std::pair{cx - hx, cy - hy}})
    stops_.push_back({{x, y, ze}, Plane::kElevation, true});
  // Object plane, continuing from the lower left.
  const double x0 = in, x1 = cell.field_length_mm - in, y0 = in, y1 = cell.field_width_mm - in;
  for (const auto& [x, y] : {std::pair{x0, y0}, std::pair{cx, y0}, std::pair{x1, y0},
                             std::pair{x1, y1}, std::pair{cx, y1}, std::pair{x0, y1}}) {
    const bool via = config.approach_from_elevation && arm::reachable_tool_down(cell, x, y, ze) &&
                     !stops_.empty();
    if (via) stops_.push_back({{x, y, ze}, Plane::kElevation, false});
    stops_.push_back({{x, y, zo}, Plane::kObject, true});
    if (via) stops_.push_back({{x, y, ze}, Plane::kElevation, false});
  }
  check(cell);
}

CalibrationPlan::CalibrationPlan(const geometry::Workcell& cell, std::vector<CalibrationStop> stops)
    : stops_(std::move(stops)) {
  check(cell);
}

int CalibrationPlan::measured(Plane plane) const {
  int n = 0;
  for (const auto& s : stops_) n += s.measure && s.plane == plane ? 1 : 0;
  return n;
}

void CalibrationPlan::check(const geometry::Workcell& cell) const {
  for (const auto& s : stops_) {
    if (!s.tip_mm.allFinite()) throw std::invalid_argument("calibration point is not finite");
    if (!arm::reachable_tool_down(cell, s.tip_mm.x(), s.tip_mm.y(), s.tip_mm.z()))
      throw std::invalid_argument("calibration point " + describe(s) +
                                  " is out of the arm's reach with the tool pointing down");
  }
  if (measured(Plane::kObject) < 3)
    throw std::invalid_argument("a calibration plan needs >= 3 object-plane points");
  if (measured(Plane::kElevation) < 1)
    throw std::invalid_argument("a calibration plan needs >= 1 elevation-plane point");
}

}  // namespace ephor::calibrate
