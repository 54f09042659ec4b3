#pragma once
// The light-stripe sensor's geometry (paper 004, section 2): the camera's
// projection P, and the poses of the camera (C_T) and of the stripe projector
// (S_T) on the robot's wrist flange.
//
// Frames and units (mm, rad, pixels):
// - Flange frame: the PUMA 560's frame 6 (z6 the approach axis).
// - Camera frame (the paper's C): origin at the lens centre, z along the
//   principal ray (out of the lens), x along the image columns (u grows to the
//   right), y along the rows (v grows downward): OpenCV's convention.
// - Projector frame (the paper's S): origin at the cylindrical lens, the
//   light plane is its y-z plane (x = 0), z the direction of projection, the
//   stripe fans out along y.
// - Image: u = column, v = row, pixel centres at integer coordinates,
//   (0, 0) the centre of the top-left pixel.

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace ephor::stripe {

// Pinhole intrinsics of the camera (no distortion), pixels.
struct CameraIntrinsics {
  int width_px = 256;
  int height_px = 256;
  double fx_px = 625.0;  // focal length / pixel pitch along u
  double fy_px = 625.0;  // focal length / pixel pitch along v
  double cx_px = 127.5;  // principal point, u
  double cy_px = 127.5;  // principal point, v

  // The paper's CID camera: 256 x 256 elements behind a 25 mm lens. We take a
  // 40 um element pitch (a 10.2 mm square sensor; the paper does not give
  // it), so f = 25 mm / 0.04 mm = 625 px and the view is 140 mm wide at
  // 342 mm, where the camera meets the stripe 300 mm from the projector.
  static CameraIntrinsics paper_camera();

  // The paper's P as a 4 x 4 homogeneous matrix (Duda & Hart): P maps a camera
  // point [X Y Z 1] to [fx X + cx Z, fy Y + cy Z, 1, Z], i.e. after division
  // by the last element to [u v 1/Z 1]: the third image coordinate carries
  // the inverse depth, so P is invertible and P^-1 maps an image point
  // [u v w 1] back to the camera point at depth Z = 1/w on the pixel's ray.
  Eigen::Matrix4d projection_matrix() const;
  Eigen::Matrix4d inverse_projection_matrix() const;

  // Pixel of a camera-frame point (Z > 0).
  Eigen::Vector2d project(const Eigen::Vector3d& p_camera) const;
  // Unit ray direction in the camera frame through pixel (u, v).
  Eigen::Vector3d ray(double u, double v) const;

  bool valid() const;
};

// The projected light sheet: "a stripe of light about 200 mm long and 1 mm
// wide at a distance of 300 mm from the lens" (section 2).
struct LaserSheet {
  double fan_half_angle_rad = 0.32175;  // atan(100 / 300): 200 mm long at 300 mm
  double width_fwhm_mm = 1.0;           // sheet thickness (full width at half maximum)
  double reference_range_mm = 300.0;    // where the two figures above hold
};

// What the software believes (or the simulator knows) about the sensor on
// the flange: the paper's C_T and S_T and P.
struct SensorCalibration {
  Eigen::Isometry3d camera_in_flange = Eigen::Isometry3d::Identity();  // C_T: camera -> flange
  Eigen::Isometry3d projector_in_flange =
      Eigen::Isometry3d::Identity();  // S_T: projector -> flange
  CameraIntrinsics camera;

  // The cage "from the mechanical drawings": the projector 80 mm out along
  // z6 looking along z6 with its light plane the flange's y-z plane; the
  // camera 120 mm beside it along x6 (and 20 mm nearer the flange), its
  // principal ray through the stripe's centre 300 mm from the projector and
  // its rows along y6, so the stripe runs top to bottom in the image and
  // range moves it across (the paper's "generally top-to-bottom" stripes).
  // Triangulation angle 20.6 deg.
  static SensorCalibration drawing_cage();
};

// A look-at pose: origin `eye`, z towards `target`, y as near `up_hint` as
// possible. Returns the frame -> parent transform.
Eigen::Isometry3d look_at(const Eigen::Vector3d& eye, const Eigen::Vector3d& target,
                          const Eigen::Vector3d& up_hint);

}  // namespace ephor::stripe
