#pragma once
// The calibrate process's procedure (paper 004, sections 3 and 4, then one
// joint refinement beyond the paper), through a CalibrationRig (the bus to
// the shared arm and the camera in ephor-stripe-calibrate; the simulated
// world in tests), from a starting calibration (the drawing's, or an older
// file), each step reporting its correction as the paper's program did:
//
//  1. joint zero references 2-5 by the camera (section 3, ZeroReferenceCalibrator:
//     the table's spot from many poses; C_T fitted with them, joint 6 in it);
//  2. wrist (section 4's joint 6 step): carried by C_T's turn about z6 in step 1;
//  3. camera aim (the spot kept centred while the camera rises);
//  4. camera scale and roll (the spot's motion as the camera steps sideways);
//  5. projector plane (the stripe on the table top from several heights);
//  6. the joint refinement (Ceres) of zero references, C_T, the light plane
//     and links 1-5 over the spot sightings and stripes on the table,
//     reporting the residual and what it could not absorb.
//
// Units: mm, degrees in the report; the table frame.

#include <functional>
#include <string>
#include <vector>

#include "common/stripe/calibration_file.h"
#include "common/stripe/calibration_refiner.h"
#include "common/stripe/scan_geometry.h"
#include "common/stripe/sensor_calibrator.h"
#include "common/stripe/zero_reference_calibrator.h"

namespace ephor::stripe {

enum class CalibrationViews {
  kFull,   // the library's view sets (about 220 views, a few minutes of arm motion)
  kQuick,  // fewer views of each kind (about 40: under a minute), for tests and a quick check
};
const char* to_string(CalibrationViews v);
// "full" or "quick"; throws std::invalid_argument otherwise.
CalibrationViews parse_calibration_views(const std::string& name);

struct CalibrationRunOptions {
  CalibrationViews views = CalibrationViews::kFull;
  // Section 3's views in every arm branch (righty / lefty, elbow, wrist
  // flip): only for an arm that goes to a joint goal in the configuration
  // asked for. Today's ephor-arm reaches a joint goal's pose in the
  // configuration it is in, so the default is the working branch only.
  bool all_branches = false;
  // Where the software believes the table's spot is (table frame, mm).
  Eigen::Vector2d spot_guess_mm = Eigen::Vector2d::Zero();
  // The refinement also fits links 1-5's DH errors (beyond the paper's model).
  bool link_errors = true;
};

// The options of each step for a preset (exposed for the tests and bench).
ZeroReferenceOptions zero_reference_options(const CalibrationRunOptions& o);
std::vector<double> projector_heights_mm(const CalibrationRunOptions& o);
CalibrationRefinerOptions refiner_options(const CalibrationRunOptions& o);

struct CalibrationRunResult {
  StripeCalibration calibration;     // the new file's contents (robot_seed as the start's)
  std::vector<std::string> report;   // one line per step (also in calibration.report)
  ZeroReferenceResult zero;          // step 1
  CalibrationRefinement refinement;  // step 6
  int views = 0;                     // images taken
};

// Runs the six steps from `start` (its robot_seed is kept); `progress`, when
// given, gets each report line as its step ends. Throws CalibrationError
// when a step cannot go on (the spot lost, too few views).
CalibrationRunResult run_calibration(CalibrationRig& rig, const StripeWorkcell& cell,
                                     const StripeCalibration& start,
                                     const CalibrationRunOptions& options,
                                     const std::function<void(const std::string&)>& progress = {});

}  // namespace ephor::stripe
