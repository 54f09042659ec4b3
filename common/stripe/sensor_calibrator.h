#pragma once
// Section 4 of paper 004, automated: camera aim (the contrasting spot kept
// centred while the camera rises) and the projector's light plane (the
// stripe on the known table top, seen from several heights, fitted by least
// squares in the flange frame). Each step starts from the current
// calibration and returns the corrected one and the correction it made.
//
// The procedures talk to the sensor through CalibrationRig (move the arm to
// joint readings, take an image), so a process can drive a real or the
// simulated rig; SimulatedRig wraps StripeWorld.

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <vector>

#include <opencv2/core.hpp>

#include "common/stripe/scan_geometry.h"
#include "common/stripe/stripe_extractor.h"
#include "common/stripe/stripe_world.h"
#include "common/stripe/true_arm.h"

namespace ephor::stripe {

class CalibrationError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class CalibrationRig {
 public:
  virtual ~CalibrationRig() = default;
  // Move to joint readings q and take the stripe image (filter on, laser on).
  virtual cv::Mat stripe_image(const arm::Joints& q) = 0;
  // Move to q and take the image with the filter removed and the laser off.
  virtual cv::Mat spot_image(const arm::Joints& q) = 0;
  // The joint readings the last image was taken at, for the fits: a real arm
  // stops near the commanded readings (within its servo's tolerance), not at
  // them, and may reach the same flange pose in another representation.
  // `commanded` is what the last image call asked for; a rig that knows no
  // better returns it.
  virtual arm::Joints readings(const arm::Joints& commanded) const { return commanded; }
};

class SimulatedRig : public CalibrationRig {
 public:
  // `world` must outlive the rig; images get seeds seed, seed + 1, ...
  SimulatedRig(const StripeWorld& world, std::uint64_t seed) : world_(&world), seed_(seed) {}
  cv::Mat stripe_image(const arm::Joints& q) override { return world_->image(q, seed_++); }
  cv::Mat spot_image(const arm::Joints& q) override { return world_->spot_image(q, seed_++); }

 private:
  const StripeWorld* world_;
  std::uint64_t seed_;
};

// Centroid (pixels) of the largest dark blob (below `threshold`) weighted by
// its darkness; nullopt when there is none or it touches the image border.
std::optional<Eigen::Vector2d> find_spot(const cv::Mat& image, int threshold = 100);

struct CameraAimResult {
  SensorCalibration updated;
  double correction_deg = 0.0;                              // angle the principal ray was turned by
  Eigen::Vector2d spot_shift_px = Eigen::Vector2d::Zero();  // spot motion on rising
};

// Section 4's camera aim: the camera aimed straight down (by the current
// calibration) `height_mm` above the spot at `spot_xy_mm`, moved until the
// spot is at the principal point, then raised `raise_mm`; the spot's motion
// gives the principal ray's tilt, which corrects C_T's rotation. Throws
// CalibrationError when the spot is lost or a pose is out of reach.
CameraAimResult calibrate_camera_aim(CalibrationRig& rig, const StripeWorkcell& cell,
                                     const TrueArm& model, const SensorCalibration& current,
                                     const Eigen::Vector2d& spot_xy_mm, double height_mm = 300.0,
                                     double raise_mm = 100.0);

struct CameraScaleRollResult {
  SensorCalibration updated;
  double fx_ratio = 1.0;             // new horizontal magnification (fx) over the old
  double fy_ratio = 1.0;             // new vertical magnification (fy) over the old
  double roll_correction_deg = 0.0;  // C_T turned about the principal ray by this
  Eigen::Vector2d x_move_px = Eigen::Vector2d::Zero();  // spot motion per +step along camera x
  Eigen::Vector2d y_move_px = Eigen::Vector2d::Zero();  // ... along camera y
};

// Section 4's camera scale and roll: the camera straight down (by the
// current calibration) `height_mm` above the spot at `spot_xy_mm`, the spot
// centred, then moved +-step_mm along the camera's believed x and y axes
// at the same height and orientation. The spot's image motion over the
// physical motion gives each magnification (fx, fy: the depth is the
// height the model believes); motion across the expected direction gives
// the roll about the principal ray, corrected in C_T. Throws
// CalibrationError when the spot is lost or a pose is out of reach.
CameraScaleRollResult calibrate_camera_scale_and_roll(
    CalibrationRig& rig, const StripeWorkcell& cell, const TrueArm& model,
    const SensorCalibration& current, const Eigen::Vector2d& spot_xy_mm, double height_mm = 300.0,
    double step_mm = 25.0);

struct ProjectorPlaneResult {
  SensorCalibration updated;
  double normal_change_deg = 0.0;  // between the old and new light-plane normals
  double offset_change_mm = 0.0;   // the old projector origin's distance from the new plane
  double rms_mm = 0.0;             // the fit's 1 sigma, flange frame
  size_t points = 0;
};

// Section 4's projector calibration: the stripe on the table top (z = 0)
// from the projector looking down at (x, y) from each height, also pitched
// +-8 deg along the stripe; each stripe point is the current camera's ray
// met with the table, carried into the flange frame; the light plane is
// their least-squares plane. Throws CalibrationError when fewer than 100
// points are seen or a pose is out of reach.
ProjectorPlaneResult calibrate_projector_plane(
    CalibrationRig& rig, const StripeWorkcell& cell, const TrueArm& model,
    const SensorCalibration& current, const Eigen::Vector2d& centre_xy_mm,
    const std::vector<double>& heights_mm = {250.0, 290.0, 330.0, 370.0});

}  // namespace ephor::stripe
