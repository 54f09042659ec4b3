#pragma once
// FieldCalibration: the image-to-field transform of paper 003, section 5,
// equation (1). The overhead camera looks straight down, so every plane
// parallel to the table maps to the image by an affine map; one 2 x 3 matrix
// per working plane of the manipulator tip (object plane: touches sheep;
// elevation plane: free travel). Because the camera is a perspective camera,
// the elevation plane's map differs from the object plane's: the paper takes
// a fourth point for it.
//
// Frames: image px (u right, v down, origin at the centre of the top-left
// pixel, as common/geometry/overhead_camera.h); field frame F in mm
// (common/geometry/workcell.h).
//
// Immutable after construction; safe to share between threads.

#include <string>
#include <vector>

#include <Eigen/Core>

#include "common/geometry/overhead_camera.h"
#include "common/geometry/workcell.h"

namespace ephor::calibration {

enum class Plane { kObject, kElevation };

// One image point and the field point it shows.
struct Correspondence {
  Eigen::Vector2d image_px;  // (u, v), px
  Eigen::Vector2d field_mm;  // (x, y) in F, mm
};

// Row-major 2 x 3: [x; y] = M * [u; v; 1].
using AffineMap = Eigen::Matrix<double, 2, 3>;

// Heights of the two planes in F (mm) and the image centre (px) about which a
// one-point elevation fit scales; defaults match Workcell and OverheadCamera.
struct PlaneSetup {
  double object_plane_z_mm = geometry::Workcell{}.object_plane_z_mm;
  double elevation_plane_z_mm = geometry::Workcell{}.elevation_plane_z_mm;
  Eigen::Vector2d image_centre_px{geometry::OverheadCamera{}.cu_px,
                                  geometry::OverheadCamera{}.cv_px};
};

class FieldCalibration {
 public:
  // Direct construction; throws std::invalid_argument if a matrix is not
  // finite or is singular (its 2 x 2 linear part has no inverse).
  FieldCalibration(const AffineMap& object_plane, const AffineMap& elevation_plane,
                   PlaneSetup planes, std::vector<Correspondence> object_points = {},
                   std::vector<Correspondence> elevation_points = {}, std::string source = "");

  // Image (px) -> F (mm) in the given plane: equation (1).
  Eigen::Vector2d image_to_field(double u_px, double v_px, Plane plane) const;
  // F (mm) -> image (px): the inverse of the affine map of that plane.
  Eigen::Vector2d field_to_image(double x_mm, double y_mm, Plane plane) const;
  // Converts a direction (e.g. a velocity, px/s) from image to F (mm/s): the
  // linear part only.
  Eigen::Vector2d image_vector_to_field(const Eigen::Vector2d& d_px, Plane plane) const;

  // The map for a plane at height z_mm (e.g. the sheep's marks), interpolated
  // (extrapolated) linearly between the two calibrated planes. Exact for a
  // camera looking straight down: its mm-per-px scale and offset are both
  // linear in (camera height - z).
  AffineMap matrix_at_height(double z_mm) const;
  Eigen::Vector2d image_to_field_at_height(double u_px, double v_px, double z_mm) const;

  const AffineMap& matrix(Plane plane) const;
  double plane_z_mm(Plane plane) const;
  const PlaneSetup& planes() const { return planes_; }
  const std::vector<Correspondence>& object_points() const { return object_points_; }
  const std::vector<Correspondence>& elevation_points() const { return elevation_points_; }
  const std::string& source() const { return source_; }

  // Reads a Protobuf text calibration (calibration.proto). Throws ConfigError
  // "path:line: field: problem" for a missing file, a syntax error, a missing
  // matrix element or plane height, a NaN/inf value or a singular matrix.
  static FieldCalibration load(const std::string& path);
  // Same, from text in memory; `name` stands for the file in errors.
  static FieldCalibration parse(const std::string& text, const std::string& name);
  // Writes the calibration as Protobuf text. `header_comment` (may be several
  // lines) is written first as '#' comments. Throws ConfigError on I/O error.
  void save(const std::string& path, const std::string& header_comment = "") const;
  std::string to_text(const std::string& header_comment = "") const;

  // Fits both maps from correspondences (paper: three points for the object
  // plane, a fourth for the elevation plane).
  //  - object_points: >= 3, not collinear; least squares when more.
  //  - elevation_points: >= 3 (not collinear): its own least-squares affine;
  //    1 or 2: the object map scaled about planes.image_centre_px, the one
  //    scale factor chosen (least squares) so the points fit. That is exact
  //    for a camera looking straight down with its principal point there.
  // Throws std::invalid_argument with the reason on too few, non-finite or
  // degenerate points.
  static FieldCalibration fit(const std::vector<Correspondence>& object_points,
                              const std::vector<Correspondence>& elevation_points,
                              PlaneSetup planes = {});

  // Fits from the true camera at the four field corners in each plane: the
  // simulator's calibration (exact to rounding, the sim camera being a
  // straight-down pinhole).
  static FieldCalibration from_camera(const geometry::OverheadCamera& camera,
                                      const geometry::Workcell& workcell);

 private:
  AffineMap object_;
  AffineMap elevation_;
  Eigen::Matrix2d object_inv_;     // inverse of object_'s linear part
  Eigen::Matrix2d elevation_inv_;  // inverse of elevation_'s linear part
  PlaneSetup planes_;
  std::vector<Correspondence> object_points_;
  std::vector<Correspondence> elevation_points_;
  std::string source_;
};

}  // namespace ephor::calibration
