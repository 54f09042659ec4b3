#pragma once
// ephor-rambo-predictor's fit task, out of main.cc so that the fuzz target
// predictor_task_fuzz.cc runs what the process runs: a RAMBO_POSE checked
// (found, finite, a rotation, reprojection error, newer than the last),
// dropped when it is far off the fitted motion (unless refit_after in a row
// are), added to the window of the last window_s, the model fitted and the
// RAMBO_PREDICTION it publishes built. Not thread-safe: the fit task's own.

#include <cstdint>
#include <deque>
#include <optional>
#include <utility>

#include <Eigen/Geometry>

#include "common/rambo/polynomial_pose_predictor.h"
#include "common/rambo/rigid_body_pose_predictor.h"
#include "ephor/rambo_pose_t.hpp"
#include "ephor/rambo_prediction_t.hpp"

namespace ephor::rambo {

// The process's flags (their defaults).
struct PoseFitterOptions {
  bool polynomial = false;  // the polynomial fits, else the rigid body
  double window_s = 4.0;    // fit the poses of this last span, s (the model's window)
  int min_samples = 5;      // poses needed for a fit
  double max_rms_px = 3.0;  // poses with more reprojection error are dropped, px
  int refit_after = 10;     // outlier poses in a row that restart the fit
  double max_jump_mm = 40.0, max_jump_deg = 15.0;  // an outlier: this far off the fit
  int poly_degree = 2;
  RotationCoordinates poly_rotation = RotationCoordinates::kZyxAngles;
  Eigen::Vector3d principal_moments = Eigen::Vector3d::Ones();  // the cell's (rigid body)
};

class PoseFitter {
 public:
  // A pose whose target is farther than this from the base is dropped, mm:
  // the workcell is a few metres across, and a pose of 1e304 mm (a bad
  // message) fitted to an infinite uncertainty (fuzz target rambo_predictor).
  static constexpr double kMaxDistanceMm = 1e6;
  // A pose this long after the last one in the window starts the fit afresh
  // instead of being checked against the old fit's prediction, s: the
  // rigid body's prediction integrates across the gap in 5 ms steps (a
  // year's gap would hold the task for hours), and no reader keeps a
  // prediction this old (the planner's longest is 8 s).
  static constexpr double kMaxGapS = 60.0;

  explicit PoseFitter(const PoseFitterOptions& options);

  // One RAMBO_POSE as the fit task takes it: the RAMBO_PREDICTION to
  // publish (utime now_us, wall clock), or nullopt when the pose is not
  // found or dropped. Times inside are seconds since the first pose used (a
  // fit in absolute epoch seconds would lose precision); the message
  // carries absolute utimes. A fit whose prediction is not finite is a
  // failed fit (counted; the message says why, not fitted).
  std::optional<rambo_prediction_t> on_pose(const rambo_pose_t& m, int64_t now_us);

  const PosePredictor& predictor() const { return *predictor_; }
  int64_t fits() const { return fits_; }
  int64_t failures() const { return failures_; }
  int64_t dropped() const { return dropped_; }

 private:
  PoseFitterOptions options_;
  RigidBodyPosePredictor rigid_;
  PolynomialPosePredictor poly_;
  PosePredictor* predictor_;
  std::deque<std::pair<int64_t, Eigen::Isometry3d>> window_;  // utime (us), target in base (mm)
  int64_t epoch_utime_ = -1;
  int outliers_in_row_ = 0;
  bool fit_valid_ = false;  // the predictor's fit is of the poses in the window
  int64_t fits_ = 0, failures_ = 0, dropped_ = 0;
};

}  // namespace ephor::rambo
