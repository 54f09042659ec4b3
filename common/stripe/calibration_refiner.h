#pragma once
// Beyond the paper (issue 16): one least-squares refinement of everything
// sections 3 and 4 find one at a time - the zero references of joints 2-5,
// the camera's pose on the flange (C_T, carrying joint 6's zero reference),
// the light plane (S_T's plane) and the spot's place - over many views:
// the spot sightings of the zero-reference step (pixels) and the laser
// stripe on the table top (z = 0) seen from the working arm configuration
// at the distances, tilts and stripe directions of section 5's scans (each
// stripe point, triangulated, must lie on the table). What the model
// cannot absorb (the link errors no calibration here models, image noise)
// stays in the residuals, reported before and after.
//
// Units: mm, rad, pixels; frames as sensor_model.h.

#include <vector>

#include <Eigen/Core>

#include "common/stripe/scan_geometry.h"
#include "common/stripe/sensor_calibrator.h"
#include "common/stripe/true_arm.h"
#include "common/stripe/zero_reference_calibrator.h"

namespace ephor::stripe {

struct CalibrationRefinerOptions {
  // Stripe views of the empty table: the projector looking at each centre
  // (table frame, mm) straight down and tilted by tilt_deg towards each of
  // `azimuths` directions, the stripe along x and along y, from each
  // distance (mm); joint readings from the working configuration
  // (StripeWorkcell::reference_joints()).
  std::vector<Eigen::Vector2d> centres_mm = {
      {0.0, 0.0}, {60.0, 0.0}, {-60.0, 0.0}, {0.0, 60.0}, {0.0, -60.0}};
  std::vector<double> distances_mm = {270.0, 330.0};
  double tilt_deg = 25.0;
  int azimuths = 4;
  int rows_step = 16;  // every this many stripe rows are used
  // Spot sightings of the refiner's own, in the working configuration: the
  // camera's ray at the spot (or aim_offset_mm beside it, in turn) from
  // each distance, straight down and tilted by tilt_deg towards each of
  // spot_azimuths directions, the image turned by each roll.
  std::vector<double> spot_distances_mm = {300.0, 360.0};
  int spot_azimuths = 8;
  std::vector<double> spot_rolls_deg = {0.0, 90.0};
  double aim_offset_mm = 30.0;
  // Whether the zero-reference step's sightings (every arm branch) join in:
  // they pin the zero references but pull the fit towards branches the
  // scans never use, where the unmodelled link errors differ.
  bool use_all_branch_sightings = true;
  // Also fit links 1-5's DH errors (d, a, alpha): beyond the paper's model,
  // for what the zero references cannot absorb.
  bool link_errors = false;
  double link_length_prior_mm = 0.5;  // 1 sigma of d and a about the drawing's values
  double link_twist_prior_deg = 0.1;  // 1 sigma of alpha
  // Weights: residuals are divided by these (what the model is expected to
  // leave: mostly the link errors, not the image noise).
  double spot_sigma_px = 0.5;
  double table_sigma_mm = 0.2;
  double spot_radius_mm = 8.0;
  int min_stripe_points = 200;
  // Visit the views in the order that moves the arm least (greedy, by the
  // joints' travel at their speed limits) instead of as listed: for a real
  // arm, where the stripe turning between x and y at every view costs a
  // second each.
  bool order_for_travel = false;
};

struct TableStripeView {
  arm::Joints joints;                      // readings, rad
  std::vector<Eigen::Vector2d> points_px;  // (u, row) of stripe points
};

struct CalibrationRefinement {
  arm::Joints zero_offset_rad = arm::Joints::Zero();
  arm::Joints correction_rad = arm::Joints::Zero();  // from the starting model
  TrueArm arm;  // the refined arm model (zero references and, with link_errors, links)
  SensorCalibration updated;  // C_T and S_T refined
  Eigen::Vector2d spot_mm = Eigen::Vector2d::Zero();
  double camera_change_mm = 0.0, camera_change_deg = 0.0;  // C_T's change
  double plane_change_deg = 0.0, plane_change_mm = 0.0;    // the light plane's
  // Residuals before (the starting calibration) and after: spot pixels and
  // stripe points' heights above the table (mm).
  double spot_rms_before_px = 0.0, spot_rms_px = 0.0, spot_max_px = 0.0;
  double table_rms_before_mm = 0.0, table_rms_mm = 0.0, table_max_mm = 0.0;
  size_t spot_sightings = 0, stripe_views = 0, stripe_points = 0;
  int iterations = 0;
  double condition = 0.0;
};

class CalibrationRefiner {
 public:
  explicit CalibrationRefiner(StripeWorkcell cell, CalibrationRefinerOptions options = {});

  // Takes the stripe views through the rig (filter on, laser on) with
  // `model` and `current`, then refines from them. `spots`: the sightings
  // of the zero-reference step. Throws CalibrationError when fewer than
  // min_stripe_points stripe points are seen.
  CalibrationRefinement refine(CalibrationRig& rig, const TrueArm& model,
                               const SensorCalibration& current,
                               const std::vector<SpotSighting>& spots,
                               const Eigen::Vector2d& spot_guess_mm) const;

  // The fit alone.
  CalibrationRefinement fit(const std::vector<TableStripeView>& stripes,
                            const std::vector<SpotSighting>& spots, const TrueArm& model,
                            const SensorCalibration& current,
                            const Eigen::Vector2d& spot_guess_mm) const;

 private:
  StripeWorkcell cell_;
  CalibrationRefinerOptions options_;
};

}  // namespace ephor::stripe
