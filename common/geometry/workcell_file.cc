#include "common/geometry/workcell_file.h"

#include <cmath>
#include <numbers>

#include "common/config/repo_paths.h"
#include "common/config/text_proto.h"
#include "common/geometry/workcell.pb.h"

namespace ephor::geometry {

Workcell load_workcell_file(const std::string& path) {
  config::WorkcellFile file;
  const TextProto text(path, &file);
  Workcell cell;
  // Copies a set field after checking it; `positive` for sizes.
  auto take = [&](bool has, double value, const char* name, double* into, bool positive) {
    if (!has) return;
    if (!std::isfinite(value)) text.fail(name, "must be a finite number");
    if (positive && value <= 0.0) text.fail(name, "must be > 0, is " + std::to_string(value));
    *into = value;
  };
  take(file.has_field_length_mm(), file.field_length_mm(), "field_length_mm", &cell.field_length_mm,
       true);
  take(file.has_field_width_mm(), file.field_width_mm(), "field_width_mm", &cell.field_width_mm,
       true);
  take(file.has_elevation_plane_z_mm(), file.elevation_plane_z_mm(), "elevation_plane_z_mm",
       &cell.elevation_plane_z_mm, false);
  take(file.has_object_plane_z_mm(), file.object_plane_z_mm(), "object_plane_z_mm",
       &cell.object_plane_z_mm, false);
  take(file.has_base_x_mm(), file.base_x_mm(), "base_x_mm", &cell.base_x_mm, false);
  take(file.has_base_y_mm(), file.base_y_mm(), "base_y_mm", &cell.base_y_mm, false);
  take(file.has_base_z_mm(), file.base_z_mm(), "base_z_mm", &cell.base_z_mm, true);
  double yaw_deg = cell.base_yaw_rad * 180.0 / std::numbers::pi;
  take(file.has_base_yaw_deg(), file.base_yaw_deg(), "base_yaw_deg", &yaw_deg, false);
  if (std::abs(yaw_deg) > 180.0) text.fail("base_yaw_deg", "must be within +-180");
  cell.base_yaw_rad = yaw_deg * std::numbers::pi / 180.0;
  take(file.has_pedestal_radius_mm(), file.pedestal_radius_mm(), "pedestal_radius_mm",
       &cell.pedestal_radius_mm, true);
  take(file.has_tool_length_mm(), file.tool_length_mm(), "tool_length_mm", &cell.tool_length_mm,
       true);
  take(file.has_tool_accel_mm_s2(), file.tool_accel_mm_s2(), "tool_accel_mm_s2",
       &cell.tool_accel_mm_s2, true);
  return cell;
}

Workcell workcell_from_flag(const std::string& path) {
  return path.empty() ? Workcell{} : load_workcell_file(resolve_repo_path(path));
}

}  // namespace ephor::geometry
