#pragma once
// ExitSpread: the distribution of the ball's exit, not only its most likely
// value. On a pegged board the exit is chaotic: a velocity error of a few
// mm/s bounced off two or three pegs flips the path to the other side of a
// peg, and the single prediction from the filter's mean (ExitPredictor)
// settles late (measured: the exit predicted from the true state settles
// 0.5 s ahead for 44 of 50 balls, the filter's for 26). So: draw `samples`
// states from the filter's N(mean, covariance) and, for each, the pegs'
// centres from their survey error (peg_sigma_mm per axis), roll each one
// past the pegs with ExitPredictor, and report where they leave the board
// and cross the catch plane.
//
// The cover: the point of the catch plane that has the most sampled catch
// points within capture_radius_mm (the cup's inner radius minus the ball's:
// a ball whose centre falls within it is caught). Found among the samples'
// own points (each a candidate centre), then moved to the mean of the
// points it covers (and counted again there, kept only if it covers no
// fewer); ties go to the candidate whose covered points lie closest to it.
// cover_fraction is the share of all samples (including those that never
// leave within the horizon) it covers: the chance, as far as the model
// knows, that a cup there catches the ball.
//
// Deterministic: the draws come from std::mt19937_64(seed), the same numbers
// on every call (common random numbers: consecutive frames' spreads differ
// only by the state, not by the draw). The mean state itself is always the
// first sample (no noise), so samples = 1 is the plain prediction.
//
// Cost: one ExitPredictor roll per sample (0.5 ms steps over the remaining
// descent), times `samples`: 2.1 ms CPU for 32 samples from the top of the
// board past 16 pegs, 1.7 ms per BallWorldModel::update on average over a
// descent (ephor-bench-catch-worldmodel, 2026-11-28, at load 35-70: rough).
// Const methods; safe from any thread.

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "common/catch/worldmodel/exit_predictor.h"

namespace ephor::catching {

struct ExitSpreadParams {
  int samples = 32;
  double peg_sigma_mm = 0.5;        // the pegs' survey error, per axis (as ephor-catch-sim's)
  double capture_radius_mm = 30.0;  // the cup's: 50 mm inner radius - 20 mm ball radius
  uint64_t seed = 1;
};

struct ExitSample {
  double exit_x_b_mm = 0.0;
  double time_to_catch_s = 0.0;
  Eigen::Vector3d catch_point_w_mm = Eigen::Vector3d::Zero();
  int peg_bounces = 0;
};

struct ExitSpreadResult {
  bool ok = false;                // at least one sample leaves the board
  int samples = 0;                // drawn
  std::vector<ExitSample> exits;  // those that leave the board (the mean state's first, if it does)
  // The cover (see above): the point in the catch plane (W, mm), its exit x
  // (B, the mean of the covered samples') and catch time (s from the state's
  // time, their mean), the share of all samples within capture_radius_mm.
  Eigen::Vector3d cover_point_w_mm = Eigen::Vector3d::Zero();
  double cover_exit_x_b_mm = 0.0;
  double cover_time_to_catch_s = 0.0;
  double cover_fraction = 0.0;
  // Spread of the sampled exits along the edge: the 10th to 90th
  // percentile of exit x (B, mm), and the standard deviation.
  double exit_x_p10_mm = 0.0, exit_x_p90_mm = 0.0, exit_x_sd_mm = 0.0;
};

class ExitSpread {
 public:
  // Throws std::invalid_argument for samples < 1, a negative or non-finite
  // sigma or a radius <= 0.
  ExitSpread(const ExitPredictor& predictor, const ExitSpreadParams& params = {});

  // `state` = (x, y, vx, vy) in B (mm, mm/s), `covariance` its 4x4 (a
  // non-finite one gives !ok; an indefinite one is clipped to its positive
  // part).
  ExitSpreadResult sample(const Eigen::Vector4d& state, const Eigen::Matrix4d& covariance) const;

  const ExitSpreadParams& params() const { return params_; }

 private:
  ExitPredictor predictor_;
  ExitSpreadParams params_;
};

}  // namespace ephor::catching
