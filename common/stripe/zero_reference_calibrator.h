#pragma once
// Section 3 of paper 004, automated: the joints' zero references found with
// the camera as the measuring tool. The paper levels and measures a few
// special poses by hand (upper arm horizontal righty and lefty, a spirit
// level on the wrist); here, as a lab with a camera on the hand would, the
// table's contrasting spot (section 4's, filter removed, laser off) is
// looked at from many arm configurations - every inverse-kinematics branch
// (righty / lefty, elbow up / down, wrist flipped) of camera poses around
// the spot at several distances, tilts and rolls - and the zero references
// of joints 2-5, the camera's pose on the flange and the spot's place on
// the table are found together by least squares on the spot's pixel.
//
// What the software may use: joint readings it commands and the images the
// rig returns (CalibrationRig), the work cell (base in the table frame, the
// table top z = 0) and its current model and calibration. It is never told
// the arm's true errors.
//
// Why joints 1 and 6 are not estimated: joint 1's zero reference only turns
// the world about the column (the paper: "we make no attempt to correct
// joint 1"); joint 6's is indistinguishable from the cage's turn about z6
// (Rz(q6 + e) C_T = Rz(q6) (Rz(e) C_T) for every reading q6), so no camera
// measurement separates them - the paper's wrist calibration (section 4)
// levels the cage, not the flange. Here it goes into C_T: both are kept at
// the current model's values and the fitted C_T carries joint 6's error.
//
// Units: mm, rad (degrees only in names that say so), pixels; frames as
// sensor_model.h (table, PUMA base, flange, camera).

#include <string>
#include <vector>

#include <Eigen/Core>

#include "common/stripe/scan_geometry.h"
#include "common/stripe/sensor_calibrator.h"
#include "common/stripe/true_arm.h"

namespace ephor::stripe {

struct ZeroReferenceOptions {
  // Where the software believes the spot is (table frame, mm, on z = 0):
  // only the start of the fit, which estimates the spot's place too.
  Eigen::Vector2d spot_guess_mm = Eigen::Vector2d::Zero();
  // The spot's radius (mm; a lab measures it with a rule): its image's
  // centroid is predicted as the centre of the disc's perspective ellipse.
  double spot_radius_mm = 8.0;
  // Camera poses: the principal ray through the spot from these distances
  // (mm), tilted from straight down by these angles (deg) towards
  // `azimuths` directions around it, with the image turned about the ray by
  // each of `rolls_deg`. Each pose is taken in every reachable arm branch.
  std::vector<double> distances_mm = {260.0, 340.0};
  std::vector<double> tilts_deg = {0.0, 20.0, 35.0};
  int azimuths = 4;
  std::vector<double> rolls_deg = {0.0, 90.0};
  // The principal ray is aimed this far (mm, on the table) from the spot,
  // in turn +x, +y, -x, -y of the table, every other pose: with the spot
  // only ever at the image centre the camera's roll about its ray would
  // hardly show.
  double aim_offset_mm = 30.0;
  // Arm configurations whose elbow or wrist centre comes nearer the table
  // than this are not used (a lab keeps the arm off the table).
  double min_clearance_mm = 60.0;
  // Fewer spot sightings than this (after lost spots) is an error.
  int min_views = 20;
  // A second round re-plans the views with the first round's model, so
  // the spot sits nearer the image centre and fewer views are lost.
  int rounds = 2;
  // Only the working configuration's solution for each pose (the one
  // nearest StripeWorkcell::reference_joints(): shoulder right, elbow up,
  // wrist not flipped), not every branch: for an arm that reaches a joint
  // goal's pose in the configuration it is in (today's ephor-arm replans a
  // joint goal to the inverse-kinematics solution nearest its current
  // joints, common/motion/motion_planner.h), where the other branches'
  // views would only repeat the working one's. Without the righty / lefty
  // views the zero references are less well separated from C_T (the joint
  // refinement then carries them; see procs/stripe/README.md).
  bool working_branch_only = false;
  // Take the views in the order that moves the arm least (greedy, by the
  // joints' travel at their speed limits) instead of as planned.
  bool order_for_travel = false;
};

// One sighting of the spot.
struct SpotSighting {
  arm::Joints joints;       // readings, rad
  Eigen::Vector2d spot_px;  // the spot's centroid in the image
  bool lefty = false;       // shoulder branch (the paper's: cos q2 > 0 is lefty)
};

// Where find_spot puts the table's spot (a dark disc of radius_mm centred
// at spot_mm on z = 0, table frame) for the camera pose `camera_in_table`
// (camera -> table): the centroid of its image, the centre of the disc's
// perspective ellipse (not the image of the disc's centre: on a view
// tilted 35 deg from 300 mm the 8 mm spot's differ by ~0.1 px, worth 0.01
// deg on the joints). Far off-image (1e4, 1e4) when behind the camera.
Eigen::Vector2d spot_centroid_px(const Eigen::Isometry3d& camera_in_table,
                                 const Eigen::Vector3d& spot_mm, double radius_mm,
                                 const CameraIntrinsics& camera);

struct ZeroReferenceResult {
  arm::Joints zero_offset_rad = arm::Joints::Zero();  // the new model's (physical = reading + it)
  arm::Joints correction_rad = arm::Joints::Zero();   // new minus the starting model's
  SensorCalibration updated;  // the starting one with the fitted C_T (carrying joint 6's error)
  Eigen::Vector2d spot_mm = Eigen::Vector2d::Zero();  // the fitted spot, table frame
  double rms_px = 0.0;                                // residual of the fit
  double max_px = 0.0;
  size_t sightings = 0;
  int lefty_sightings = 0;
  int iterations = 0;
  // The paper's demonstration of inaccuracy: the spot located on the table
  // (each sighting's ray met with z = 0) by the lefty sightings' mean
  // minus the righty ones', mm, before (starting model) and after.
  double lefty_righty_gap_before_mm = 0.0;
  double lefty_righty_gap_after_mm = 0.0;
  // Ratio of the fit Jacobian's largest to smallest singular value (scaled
  // parameters): large means the views do not separate the unknowns.
  double condition = 0.0;
  std::vector<SpotSighting> sightings_used;  // what the fit used (for a later joint refinement)
};

class ZeroReferenceCalibrator {
 public:
  explicit ZeroReferenceCalibrator(StripeWorkcell cell, ZeroReferenceOptions options = {});

  // Plans the views with `model` and `current`, takes the spot images, fits.
  // Throws CalibrationError when too few sightings are made or the fit fails.
  ZeroReferenceResult calibrate(CalibrationRig& rig, const TrueArm& model,
                                const SensorCalibration& current) const;

  // The fit alone on given sightings, from `model` and `current`.
  ZeroReferenceResult fit(const std::vector<SpotSighting>& sightings, const TrueArm& model,
                          const SensorCalibration& current) const;

  // The joint readings (under `model`) of every planned camera pose in
  // every branch that is within limits and clear of the table.
  std::vector<arm::Joints> plan(const TrueArm& model, const SensorCalibration& current,
                                const Eigen::Vector2d& spot_mm) const;

  const ZeroReferenceOptions& options() const { return options_; }

 private:
  std::vector<SpotSighting> sight(CalibrationRig& rig, const TrueArm& model,
                                  const SensorCalibration& current,
                                  const Eigen::Vector2d& spot_mm) const;

  StripeWorkcell cell_;
  ZeroReferenceOptions options_;
};

}  // namespace ephor::stripe
