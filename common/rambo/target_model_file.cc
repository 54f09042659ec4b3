#include "common/rambo/target_model_file.h"

#include <cmath>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "common/config/repo_paths.h"
#include "common/config/text_proto.h"
#include "common/rambo/target_model.pb.h"

namespace ephor::rambo {
namespace {

// A lens farther than this from the surface (either side) is off the target, mm.
constexpr double kOnSurfaceMm = 1.0;
// A vertex this far outside a face's plane makes the model non-convex, mm.
constexpr double kConvexMm = 0.5;

std::string num(double v) {
  std::ostringstream s;
  s.precision(4);
  s << v;
  return s.str();
}

Eigen::Vector3d vec(const TextProto& src, const std::string& field, bool has,
                    const config::Vec3& v) {
  if (!has) src.fail(field, "missing");
  if (!v.has_x() || !v.has_y() || !v.has_z()) src.fail(field, "needs x, y and z");
  const Eigen::Vector3d out(v.x(), v.y(), v.z());
  if (!out.allFinite())
    src.fail(field,
             "is not finite (" + num(out.x()) + ", " + num(out.y()) + ", " + num(out.z()) + ")");
  return out;
}

TargetSpec from_proto(const config::TargetModel& p, const TextProto& src) {
  TargetSpec t;
  if (p.vertex_size() < 4)
    // (TextProto::fail needs an index for a repeated field.)
    throw ConfigError(src.path() + ": vertex: the model has " + std::to_string(p.vertex_size()) +
                      " vertices, a polyhedron needs at least 4");
  for (int i = 0; i < p.vertex_size(); ++i)
    t.vertices_mm.push_back(vec(src, "vertex[" + std::to_string(i) + "]", true, p.vertex(i)));
  const int nv = p.vertex_size();
  if (p.face_size() < 4)
    throw ConfigError(src.path() + ": face: the model has " + std::to_string(p.face_size()) +
                      " faces, a polyhedron needs at least 4");
  for (int f = 0; f < p.face_size(); ++f) {
    const std::string field = "face[" + std::to_string(f) + "]";
    const auto& face = p.face(f);
    if (face.vertex_size() < 3)
      src.fail(field,
               "has " + std::to_string(face.vertex_size()) + " vertices, a face needs at least 3");
    std::vector<int> ids;
    for (int k = 0; k < face.vertex_size(); ++k) {
      const int v = face.vertex(k);
      if (v < 0 || v >= nv)
        src.fail(field, "face " + std::to_string(f) + " index " + std::to_string(k) +
                            " names vertex " + std::to_string(v) + ", which is missing (vertices " +
                            "are 0-" + std::to_string(nv - 1) + ")");
      ids.push_back(v);
    }
    t.faces.push_back(ids);
  }
  // TargetModel's own checks (repeated vertices, faces without area).
  std::optional<TargetModel> model;
  try {
    model.emplace(t.vertices_mm, t.faces);
  } catch (const std::invalid_argument& e) {
    throw ConfigError(src.path() + ": " + e.what());
  }
  // Outward normals and visibility assume a convex polyhedron.
  for (int f = 0; f < static_cast<int>(t.faces.size()); ++f)
    for (int v = 0; v < nv; ++v) {
      const double d = model->face_normal(f).dot(
          t.vertices_mm[static_cast<std::size_t>(v)] -
          t.vertices_mm[static_cast<std::size_t>(t.faces[static_cast<std::size_t>(f)][0])]);
      if (d > kConvexMm)
        src.fail("face[" + std::to_string(f) + "]",
                 "vertex " + std::to_string(v) + " is " + num(d) + " mm outside face " +
                     std::to_string(f) + "'s plane: the model must be convex with planar faces");
    }
  if (p.diode_size() > RamboCell::kMaxDiodes)
    src.fail("diode[" + std::to_string(RamboCell::kMaxDiodes) + "]",
             "the model has " + std::to_string(p.diode_size()) + " diodes, at most " +
                 std::to_string(RamboCell::kMaxDiodes));
  double standoff = RamboCell::kStandoffMm;
  if (p.has_goal_standoff_mm()) standoff = p.goal_standoff_mm();
  if (!(standoff > 0.0 && standoff <= 1000.0))
    src.fail("goal_standoff_mm", "must be in (0, 1000] mm, is " + num(standoff));
  for (int i = 0; i < p.diode_size(); ++i) {
    const std::string field = "diode[" + std::to_string(i) + "]";
    const auto& d = p.diode(i);
    Diode out;
    out.name = d.has_name() && !d.name().empty() ? d.name() : "diode " + std::to_string(i);
    const std::string who = field + " ('" + out.name + "')";
    out.lens_mm = vec(src, field + ".lens_mm", d.has_lens_mm(), d.lens_mm());
    const Eigen::Vector3d axis = vec(src, field + ".axis", d.has_axis(), d.axis());
    if (axis.norm() < 1e-9) src.fail(field + ".axis", "is zero");
    out.axis = axis.normalized();
    out.standoff_mm = d.has_standoff_mm() ? d.standoff_mm() : standoff;
    if (!(out.standoff_mm > 0.0 && out.standoff_mm <= 1000.0))
      src.fail(field + ".standoff_mm", "must be in (0, 1000] mm, is " + num(out.standoff_mm));
    int face = -1;
    const double off = model->surface_distance_mm(out.lens_mm, &face);
    if (std::abs(off) > kOnSurfaceMm)
      src.fail(field + ".lens_mm", "goal point " + who + " is off the target: its lens is " +
                                       num(std::abs(off)) + " mm " +
                                       (off > 0 ? "outside" : "inside") + " the surface (at most " +
                                       num(kOnSurfaceMm) + " mm)");
    if (out.axis.dot(model->face_normal(face)) < 0.1)
      src.fail(field + ".axis", "goal point " + who + ": the axis does not point out of face " +
                                    std::to_string(face));
    for (const Diode& other : t.diodes)
      if (other.name == out.name) src.fail(field + ".name", "'" + out.name + "' is used twice");
    t.diodes.push_back(out);
  }
  if (p.has_principal_moments_mm2()) {
    t.principal_moments_mm2 = vec(src, "principal_moments_mm2", true, p.principal_moments_mm2());
    if (t.principal_moments_mm2.minCoeff() <= 0.0)
      src.fail("principal_moments_mm2", "must all be > 0");
  } else {
    src.fail("principal_moments_mm2", "missing (the tumble needs them)");
  }
  return t;
}

}  // namespace

TargetSpec load_target_model_file(const std::string& path) {
  config::TargetModel p;
  const TextProto src(path, &p);
  return from_proto(p, src);
}

TargetSpec parse_target_model(const std::string& text, const std::string& name) {
  config::TargetModel p;
  const auto src = TextProto::from_string(text, name, &p);
  return from_proto(p, *src);
}

TargetSpec target_from_flag(const std::string& path) {
  return path.empty() ? RamboCell::builtin_target()
                      : load_target_model_file(resolve_repo_path(path));
}

RamboCell cell_from_flags(const std::string& model_path, int diode_count) {
  const TargetSpec target = target_from_flag(model_path);
  const int available = static_cast<int>(target.diodes.size());
  const std::string model = model_path.empty() ? "the built-in target" : model_path;
  if (available == 0) throw ConfigError(model + ": carries no diodes");
  if (diode_count == 0) diode_count = available;
  if (diode_count < 1 || diode_count > available)
    throw ConfigError("--diodes " + std::to_string(diode_count) + ": " + model + " carries " +
                      std::to_string(available) + " diodes (1-" + std::to_string(available) + ")");
  try {
    return RamboCell::make(target, diode_count);
  } catch (const std::invalid_argument& e) {
    throw ConfigError(model + ": " + e.what());
  }
}

}  // namespace ephor::rambo
