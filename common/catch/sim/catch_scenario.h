#pragma once
// CatchScenario: everything about one simulated ball-catching set-up that is
// drawn at random from a seed (paper 000, section 2: "a small ball is
// released at the top of an inclined board which contains randomly placed
// pegs"; "the camera is arbitrarily positioned ... the only constraint on its
// placement is that the entire face of the board must be in the field of
// view"): the incline, the pegs, where each ball is released, the camera's
// pose and the scene's lighting and grey levels.
//
// Deterministic: the same seed (and BoardSpec) gives the same scenario on
// every run and machine that shares the standard library (std::mt19937_64 and
// the uniform distributions of libstdc++).
//
// Frames and units are those of common/catch/board_model.h: lengths in
// mm, B the board frame (z out of the face), W the work cell (z up), C the
// camera (OpenCV pinhole). The scenario is a plain value: tests and tools may
// edit its fields (remove the pegs, flatten the lighting) before handing it to
// BoardWorld or BoardRenderer.

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "common/catch/board_model.h"

namespace ephor::catching {

// A peg: a static cylinder standing on the board face, axis along z_B.
struct Peg {
  double x_mm = 0.0;  // centre, B
  double y_mm = 0.0;
};

// Fluorescent tubes over the board: parallel bright bands across the board
// face, plus the lens' vignette. The light reaching a point (x, y) of B is
// gain = base_gain + sum_k amplitude_k * exp(-d_k^2 / (2 width_k^2)), with d_k
// the distance of (x, y) from band k's centre line (direction
// band_direction_rad from x_B, passing offset_mm from the board centre along
// the line's normal). The image is then multiplied by
// 1 - vignette * r^2, r the distance from the principal point over the
// half-diagonal of the image.
struct LightBand {
  double offset_mm = 0.0;
  double width_mm = 60.0;  // Gaussian sigma across the band
  double amplitude = 0.2;  // added gain at the band's centre line
};
struct Lighting {
  double base_gain = 0.9;
  double band_direction_rad = 0.0;
  std::vector<LightBand> bands;
  double vignette = 0.15;
  // Gain at a point of the board plane (B, mm), before the vignette.
  double board_gain(double x_mm, double y_mm, const BoardSpec& board) const;
};

// Grey levels (0-255) of the scene's materials under unit light gain, and
// the camera's noise.
struct Appearance {
  double board_level = 120.0;     // the board face
  double circle_level = 20.0;     // the four black circles
  double peg_level = 60.0;        // a peg's top; its side is drawn darker
  double surround_level = 40.0;   // everything off the board (the lab)
  double surround_texture = 8.0;  // +- grey levels of smooth texture off the board
  double shadow_factor = 0.7;     // light left in a peg's shadow
  // The ball's grey minus the board's at the same point (before shading):
  // 4-8 grey levels, either sign (paper 000, section 4: "the ball ... is
  // similar in intensity to the planar surface").
  double ball_contrast = 6.0;
  double noise_sigma = 2.0;  // grey levels, per pixel per frame
};

// Where and how ball k is let go: its centre in B (mm) and velocity (mm/s).
struct BallRelease {
  double x_mm = 0.0;
  double y_mm = 0.0;
  double vx_mm_s = 0.0;
  double vy_mm_s = 0.0;
};

struct CatchScenario {
  // Draws a scenario. Throws std::invalid_argument when the board is too
  // small for the pegs or no camera pose satisfies the constraints.
  static CatchScenario draw(uint64_t seed, const BoardSpec& board = {});

  uint64_t seed = 0;
  BoardSpec board;
  BoardPlacement placement;  // incline_rad drawn in [15, 35] deg; default bottom centre
  double peg_diameter_mm = 12.0;
  double peg_height_mm = 30.0;
  std::vector<Peg> pegs;
  CameraIntrinsics intrinsics;              // no distortion
  Pose board_to_camera = Pose::Identity();  // p_C = board_to_camera * p_B
  Lighting lighting;
  Appearance appearance;
  int camera_draws = 0;  // how many camera poses were drawn before one fitted

  // p_W = board_to_world() * p_B.
  Pose board_to_world() const { return ephor::catching::board_to_world(board, placement); }
  // p_C = world_to_camera() * p_W.
  Pose world_to_camera() const { return board_to_camera * board_to_world().inverse(); }
  // The camera's optical centre in W.
  Eigen::Vector3d camera_position_w() const { return world_to_camera().inverse().translation(); }

  // Release of ball k = 0, 1, ...: a function of (seed, k) only. x uniform in
  // [r + 40, width - r - 40] at y = r + 10 (r the ball radius), velocity a
  // few mm/s in a random direction, down the slope.
  BallRelease release(int k) const;

  // Pinhole projection (distortion ignored) of a point of B; nullopt behind
  // the camera.
  std::optional<Eigen::Vector2d> project(const Eigen::Vector3d& p_b_mm) const;
  // Whether all four board corners project at least margin_px inside the image.
  bool corners_in_view(double margin_px) const;

  // The pegs as measured once when the board was set up (ephor-catch-sim's
  // CATCH_PEGS): the true centres (B, mm) with kSurveyNoiseMm of Gaussian
  // noise per axis, a function of the seed only.
  std::vector<Eigen::Vector2d> measured_pegs() const;
  // The three board points the arm's tool touched (CATCH_SURVEY; paper 000,
  // section 3): near the top corners and the bottom centre, in B (z = 0) and
  // as measured in W with kSurveyNoiseMm of noise per axis (seed only).
  struct TouchedPoints {
    std::array<Eigen::Vector2d, 3> board_mm;
    std::array<Eigen::Vector3d, 3> world_mm;
  };
  TouchedPoints touched_points() const;
};

// The constraints the draw enforces (exposed for tests).
constexpr double kInclineMinDeg = 15.0;
constexpr double kInclineMaxDeg = 35.0;
constexpr int kPegsMin = 12;
constexpr int kPegsMax = 20;
constexpr double kPegFreeTopMm = 80.0;          // release strip at the top
constexpr double kPegFreeBottomMm = 60.0;       // the last stretch before the edge
constexpr double kPegGapOverBallMm = 10.0;      // pegs' gaps exceed the ball diameter by this
constexpr double kPegCircleClearanceMm = 15.0;  // between a peg (or its shadow) and a circle
constexpr double kCornerMarginPx = 20.0;
constexpr double kSurveyNoiseMm = 0.5;  // the pegs' and the touched points' measurement, 1 sigma

}  // namespace ephor::catching
