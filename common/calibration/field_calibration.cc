#include "common/calibration/field_calibration.h"

#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <google/protobuf/text_format.h>
#include <Eigen/Dense>

#include "common/calibration/calibration.pb.h"
#include "common/config/text_proto.h"

namespace ephor::calibration {
namespace {

// A 2 x 2 linear part whose determinant is this small (mm^2/px^2) relative to
// its squared scale maps the image onto (nearly) a line: no calibration.
constexpr double kMinRelativeDet = 1e-9;

std::string fmt(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

// Empty string if `m` is usable, else the reason.
std::string matrix_problem(const AffineMap& m) {
  if (!m.allFinite()) return "matrix has a NaN or infinite element";
  const double det = m.block<2, 2>(0, 0).determinant();
  const double scale = m.block<2, 2>(0, 0).squaredNorm();
  if (!(scale > 0.0) || std::abs(det) < kMinRelativeDet * scale)
    return "singular matrix (determinant " + fmt(det) +
           " mm^2/px^2): image points would collapse onto a line";
  return "";
}

Eigen::Matrix2d linear_inverse(const AffineMap& m) { return m.block<2, 2>(0, 0).inverse(); }

// Least-squares affine fit of field = M [image; 1]. Needs >= 3 non-collinear points.
AffineMap fit_affine(const std::vector<Correspondence>& points, const std::string& what) {
  if (points.size() < 3)
    throw std::invalid_argument(what + ": need at least 3 correspondences, got " +
                                std::to_string(points.size()));
  Eigen::MatrixXd a(points.size(), 3);
  Eigen::MatrixXd b(points.size(), 2);
  for (size_t i = 0; i < points.size(); ++i) {
    const auto& p = points[i];
    if (!p.image_px.allFinite() || !p.field_mm.allFinite())
      throw std::invalid_argument(what + ": correspondence " + std::to_string(i) +
                                  " is not finite");
    a.row(static_cast<Eigen::Index>(i)) << p.image_px.x(), p.image_px.y(), 1.0;
    b.row(static_cast<Eigen::Index>(i)) = p.field_mm.transpose();
  }
  // Collinear image points leave the 3-column design rank-deficient.
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(a);
  qr.setThreshold(1e-9);
  if (qr.rank() < 3)
    throw std::invalid_argument(
        what + ": image points are collinear (or repeated); pick three that span the field");
  const Eigen::MatrixXd x = qr.solve(b);  // 3 x 2
  AffineMap m = x.transpose();
  const std::string problem = matrix_problem(m);
  if (!problem.empty()) throw std::invalid_argument(what + ": " + problem);
  return m;
}

void check_finite_double(const TextProto& src, const std::string& field, bool has, double v) {
  if (!has) src.fail(field, "missing");
  if (!std::isfinite(v)) src.fail(field, "must be a finite number, got " + fmt(v));
}

AffineMap read_map(const config::AffineMap& p, const TextProto& src, const std::string& name,
                   bool present) {
  if (!present) src.fail(name, "missing: the 2 x 3 matrix t11..t23 of this plane");
  check_finite_double(src, name + ".t11", p.has_t11(), p.t11());
  check_finite_double(src, name + ".t12", p.has_t12(), p.t12());
  check_finite_double(src, name + ".t13", p.has_t13(), p.t13());
  check_finite_double(src, name + ".t21", p.has_t21(), p.t21());
  check_finite_double(src, name + ".t22", p.has_t22(), p.t22());
  check_finite_double(src, name + ".t23", p.has_t23(), p.t23());
  AffineMap m;
  m << p.t11(), p.t12(), p.t13(), p.t21(), p.t22(), p.t23();
  const std::string problem = matrix_problem(m);
  if (!problem.empty()) src.fail(name, problem);
  return m;
}

std::vector<Correspondence> read_points(
    const google::protobuf::RepeatedPtrField<config::Correspondence>& points, const TextProto& src,
    const std::string& name) {
  std::vector<Correspondence> out;
  for (int i = 0; i < points.size(); ++i) {
    const auto& p = points.Get(i);
    const std::string f = name + "[" + std::to_string(i) + "]";
    check_finite_double(src, f + ".u_px", p.has_u_px(), p.u_px());
    check_finite_double(src, f + ".v_px", p.has_v_px(), p.v_px());
    check_finite_double(src, f + ".x_mm", p.has_x_mm(), p.x_mm());
    check_finite_double(src, f + ".y_mm", p.has_y_mm(), p.y_mm());
    out.push_back({{p.u_px(), p.v_px()}, {p.x_mm(), p.y_mm()}});
  }
  return out;
}

void write_map(const AffineMap& m, config::AffineMap* p) {
  p->set_t11(m(0, 0));
  p->set_t12(m(0, 1));
  p->set_t13(m(0, 2));
  p->set_t21(m(1, 0));
  p->set_t22(m(1, 1));
  p->set_t23(m(1, 2));
}

void write_points(const std::vector<Correspondence>& points,
                  google::protobuf::RepeatedPtrField<config::Correspondence>* out) {
  for (const auto& c : points) {
    auto* p = out->Add();
    p->set_u_px(c.image_px.x());
    p->set_v_px(c.image_px.y());
    p->set_x_mm(c.field_mm.x());
    p->set_y_mm(c.field_mm.y());
  }
}

FieldCalibration from_proto(const config::FieldCalibration& c, const TextProto& src) {
  const AffineMap object = read_map(c.object_plane(), src, "object_plane", c.has_object_plane());
  const AffineMap elevation =
      read_map(c.elevation_plane(), src, "elevation_plane", c.has_elevation_plane());
  PlaneSetup planes;
  check_finite_double(src, "object_plane_z_mm", c.has_object_plane_z_mm(), c.object_plane_z_mm());
  check_finite_double(src, "elevation_plane_z_mm", c.has_elevation_plane_z_mm(),
                      c.elevation_plane_z_mm());
  planes.object_plane_z_mm = c.object_plane_z_mm();
  planes.elevation_plane_z_mm = c.elevation_plane_z_mm();
  if (c.has_centre_u_px() || c.has_centre_v_px()) {
    check_finite_double(src, "centre_u_px", c.has_centre_u_px(), c.centre_u_px());
    check_finite_double(src, "centre_v_px", c.has_centre_v_px(), c.centre_v_px());
    planes.image_centre_px = {c.centre_u_px(), c.centre_v_px()};
  }
  return FieldCalibration(object, elevation, planes,
                          read_points(c.object_point(), src, "object_point"),
                          read_points(c.elevation_point(), src, "elevation_point"), c.source());
}

}  // namespace

FieldCalibration::FieldCalibration(const AffineMap& object_plane, const AffineMap& elevation_plane,
                                   PlaneSetup planes, std::vector<Correspondence> object_points,
                                   std::vector<Correspondence> elevation_points, std::string source)
    : object_(object_plane),
      elevation_(elevation_plane),
      planes_(std::move(planes)),
      object_points_(std::move(object_points)),
      elevation_points_(std::move(elevation_points)),
      source_(std::move(source)) {
  std::string problem = matrix_problem(object_);
  if (!problem.empty()) throw std::invalid_argument("object plane: " + problem);
  problem = matrix_problem(elevation_);
  if (!problem.empty()) throw std::invalid_argument("elevation plane: " + problem);
  object_inv_ = linear_inverse(object_);
  elevation_inv_ = linear_inverse(elevation_);
}

const AffineMap& FieldCalibration::matrix(Plane plane) const {
  return plane == Plane::kObject ? object_ : elevation_;
}

double FieldCalibration::plane_z_mm(Plane plane) const {
  return plane == Plane::kObject ? planes_.object_plane_z_mm : planes_.elevation_plane_z_mm;
}

AffineMap FieldCalibration::matrix_at_height(double z_mm) const {
  const double span = planes_.elevation_plane_z_mm - planes_.object_plane_z_mm;
  if (!(std::abs(span) > 1e-9) || !std::isfinite(z_mm)) return object_;
  const double w = (z_mm - planes_.object_plane_z_mm) / span;
  return object_ + w * (elevation_ - object_);
}

Eigen::Vector2d FieldCalibration::image_to_field_at_height(double u_px, double v_px,
                                                           double z_mm) const {
  return matrix_at_height(z_mm) * Eigen::Vector3d(u_px, v_px, 1.0);
}

Eigen::Vector2d FieldCalibration::image_to_field(double u_px, double v_px, Plane plane) const {
  return matrix(plane) * Eigen::Vector3d(u_px, v_px, 1.0);
}

Eigen::Vector2d FieldCalibration::field_to_image(double x_mm, double y_mm, Plane plane) const {
  const AffineMap& m = matrix(plane);
  const Eigen::Matrix2d& inv = plane == Plane::kObject ? object_inv_ : elevation_inv_;
  return inv * (Eigen::Vector2d(x_mm, y_mm) - m.col(2));
}

Eigen::Vector2d FieldCalibration::image_vector_to_field(const Eigen::Vector2d& d_px,
                                                        Plane plane) const {
  return matrix(plane).block<2, 2>(0, 0) * d_px;
}

FieldCalibration FieldCalibration::load(const std::string& path) {
  config::FieldCalibration c;
  const TextProto src(path, &c);
  return from_proto(c, src);
}

FieldCalibration FieldCalibration::parse(const std::string& text, const std::string& name) {
  config::FieldCalibration c;
  const auto src = TextProto::from_string(text, name, &c);
  return from_proto(c, *src);
}

std::string FieldCalibration::to_text(const std::string& header_comment) const {
  config::FieldCalibration c;
  write_map(object_, c.mutable_object_plane());
  write_map(elevation_, c.mutable_elevation_plane());
  c.set_object_plane_z_mm(planes_.object_plane_z_mm);
  c.set_elevation_plane_z_mm(planes_.elevation_plane_z_mm);
  c.set_centre_u_px(planes_.image_centre_px.x());
  c.set_centre_v_px(planes_.image_centre_px.y());
  write_points(object_points_, c.mutable_object_point());
  write_points(elevation_points_, c.mutable_elevation_point());
  c.set_source(source_);
  std::string body;
  if (!google::protobuf::TextFormat::PrintToString(c, &body))
    throw ConfigError("cannot print calibration as text");
  std::string out;
  std::istringstream lines(header_comment);
  std::string line;
  while (std::getline(lines, line)) out += "# " + line + "\n";
  return out + body;
}

void FieldCalibration::save(const std::string& path, const std::string& header_comment) const {
  const std::string text = to_text(header_comment);
  std::ofstream out(path);
  if (!out) throw ConfigError(path + ": cannot open file for writing");
  out << text;
  out.close();
  if (!out) throw ConfigError(path + ": write failed");
}

FieldCalibration FieldCalibration::fit(const std::vector<Correspondence>& object_points,
                                       const std::vector<Correspondence>& elevation_points,
                                       PlaneSetup planes) {
  if (!std::isfinite(planes.object_plane_z_mm) || !std::isfinite(planes.elevation_plane_z_mm) ||
      !planes.image_centre_px.allFinite())
    throw std::invalid_argument("plane heights and image centre must be finite");
  const AffineMap object = fit_affine(object_points, "object plane");
  AffineMap elevation;
  if (elevation_points.size() >= 3) {
    elevation = fit_affine(elevation_points, "elevation plane");
  } else if (!elevation_points.empty()) {
    // The paper's fourth point. Seen from straight above, the same (x, y)
    // appears farther from the principal point c in the higher plane, by a
    // factor s: p_elev = c + s (p_obj - c). Solve s from the points, then
    // E(p) = A (c + (p - c) / s).
    const Eigen::Vector2d c = planes.image_centre_px;
    const Eigen::Matrix2d a_inv = linear_inverse(object);
    double num = 0.0;
    double den = 0.0;
    for (size_t i = 0; i < elevation_points.size(); ++i) {
      const auto& p = elevation_points[i];
      if (!p.image_px.allFinite() || !p.field_mm.allFinite())
        throw std::invalid_argument("elevation plane: correspondence " + std::to_string(i) +
                                    " is not finite");
      const Eigen::Vector2d p_obj = a_inv * (p.field_mm - object.col(2));
      num += (p.image_px - c).dot(p_obj - c);
      den += (p_obj - c).squaredNorm();
    }
    // A point at the image centre carries no scale information.
    if (!(den > 1.0))
      throw std::invalid_argument(
          "elevation plane: the point is at the image centre; take it nearer a field corner");
    const double s = num / den;
    if (!(s > 0.0) || !std::isfinite(s))
      throw std::invalid_argument("elevation plane: the point gives a non-positive scale " +
                                  fmt(s) + " about the image centre");
    const Eigen::Matrix2d lin = object.block<2, 2>(0, 0) / s;
    elevation.block<2, 2>(0, 0) = lin;
    elevation.col(2) = object.col(2) + object.block<2, 2>(0, 0) * c - lin * c;
  } else {
    throw std::invalid_argument(
        "elevation plane: need at least 1 correspondence (the fourth point)");
  }
  return FieldCalibration(object, elevation, planes, object_points, elevation_points);
}

FieldCalibration FieldCalibration::from_camera(const geometry::OverheadCamera& camera,
                                               const geometry::Workcell& workcell) {
  const double xs[] = {0.0, workcell.field_length_mm, workcell.field_length_mm, 0.0};
  const double ys[] = {0.0, 0.0, workcell.field_width_mm, workcell.field_width_mm};
  std::vector<Correspondence> object_points;
  std::vector<Correspondence> elevation_points;
  for (int i = 0; i < 4; ++i) {
    object_points.push_back(
        {camera.project(xs[i], ys[i], workcell.object_plane_z_mm), {xs[i], ys[i]}});
    elevation_points.push_back(
        {camera.project(xs[i], ys[i], workcell.elevation_plane_z_mm), {xs[i], ys[i]}});
  }
  PlaneSetup planes;
  planes.object_plane_z_mm = workcell.object_plane_z_mm;
  planes.elevation_plane_z_mm = workcell.elevation_plane_z_mm;
  planes.image_centre_px = {camera.cu_px, camera.cv_px};
  FieldCalibration cal = fit(object_points, elevation_points, planes);
  cal.source_ = "FieldCalibration::from_camera: true pinhole camera at the four field corners";
  return cal;
}

}  // namespace ephor::calibration
