#pragma once
// BoardRenderer: the catching system's camera (paper 000, sections 3-4): 8-bit
// grey 640 x 480 frames of the inclined board, its four black circles and
// pegs, the rolling ball and the arm with its cup, seen from a CatchScenario's
// camera.
//
// What it draws (grey levels from the scenario's Appearance):
// - A static background, rendered once: each pixel's ray is cast to the
//   pegs (capped cylinders) and the board plane. Off the board: the lab,
//   dark grey ~40 with a smooth texture. On the board: the face (~120) under
//   the scenario's Lighting (bright bands of fluorescent tubes), the four
//   black circles (~20), the pegs (top ~60, darker sides) and the pegs'
//   shadows under overhead light (shadow_factor, a short streak down the
//   slope). Pixels whose corners see different surfaces are supersampled
//   8 x 8, so edges are anti-aliased by true area coverage: a circle's
//   intensity centroid is the projected ellipse's to a few hundredths of a
//   pixel.
// - Per frame, over a copy of the background: the ball (ray-sphere
//   intersection in a box around its projection; anti-aliased edge from the
//   ray's distance to the centre; grey = the lit board's grey at that pixel
//   + ball_contrast x shading in [0.55, 1], so it differs from the board it
//   rolls on by at most |ball_contrast| <= 8 grey levels; hidden by pegs in
//   front of it), then the arm's links as capsules and the cup as a capped
//   cylinder (opening up, its inside darker), dark grey, hard edges, with a
//   depth test against the board, pegs and ball: parts behind the board are
//   hidden.
// - Then the vignette (already in the background) and Gaussian pixel noise
//   (noise_sigma), read from a fixed table at a random offset per frame.
//
// Camera: the pinhole of the scenario's intrinsics; lens distortion is NOT
// applied (the scenario's intrinsics have none). Image coordinates as in
// board_model.h: pixel centres at integers.
//
// Speed (ephor-bench-catch-sim, -O3, one core, CPU time): 0.3 ms per
// 640 x 480 frame with the ball, 1.4 ms with a five-link arm and the cup in
// view (5 % of the image; the cost follows their image bounding boxes); the
// background takes ~0.1 s, once.
//
// Threading: not thread-safe; one owner renders.

#include <cstdint>
#include <optional>
#include <random>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "common/catch/board_model.h"
#include "common/catch/sim/catch_scenario.h"

namespace ephor::catching {

// A part of the arm as the camera sees it: a segment with a radius, in W (mm).
struct Capsule {
  Eigen::Vector3d a_w_mm = Eigen::Vector3d::Zero();
  Eigen::Vector3d b_w_mm = Eigen::Vector3d::Zero();
  double radius_mm = 0.0;
};

// The arm in one frame: its links and, if present, the cup's opening centre
// (the tool tip) in W; the cup hangs below it, axis vertical.
struct ArmView {
  std::vector<Capsule> links_w;
  std::optional<Eigen::Vector3d> cup_opening_w_mm;
};

class BoardRenderer {
 public:
  // Renders the background (~0.1 s). noise_seed drives the per-frame noise.
  explicit BoardRenderer(const CatchScenario& scenario, CupSpec cup = {}, uint64_t noise_seed = 1);

  int width() const { return intrinsics_.width; }
  int height() const { return intrinsics_.height; }

  // Renders one frame into `image` (made CV_8UC1 height x width). ball_b_mm:
  // the ball's centre in B (mm; nullopt: no ball in view). Returns the ball's
  // true image position (the projection of its centre) when it is in front
  // of the camera.
  std::optional<Eigen::Vector2d> render(const std::optional<Eigen::Vector3d>& ball_b_mm,
                                        const ArmView& arm, cv::Mat& image);

  // The projection of a ball centre (B, mm); nullopt behind the camera.
  std::optional<Eigen::Vector2d> ball_image_position(const Eigen::Vector3d& ball_b_mm) const;

  // The noise-free static scene, grey levels (CV_32FC1).
  const cv::Mat& background() const { return background_; }
  // The lit board face's grey at each pixel, as if the board plane filled
  // the view (CV_32FC1): what the ball's grey is relative to.
  const cv::Mat& board_level() const { return board_level_; }

 private:
  struct Sample {
    float grey;
    float depth;   // range along the ray, mm (infinity: off the board)
    int material;  // which surface the ray hit (edges are supersampled)
  };
  Sample sample(double u, double v) const;
  void render_background();
  // Reads the depth test from `depth`; writes the ball's range only if write_depth.
  void draw_ball(const Eigen::Vector3d& ball_b_mm, cv::Mat& depth, bool write_depth);
  void draw_capsule(const Capsule& c, cv::Mat& depth);
  void draw_cup(const Eigen::Vector3d& opening_w_mm, cv::Mat& depth);
  Eigen::Vector3d ray(double u, double v) const;  // unit direction in C

  CatchScenario scenario_;
  CameraIntrinsics intrinsics_;
  CupSpec cup_;
  Pose world_to_camera_;
  Pose camera_to_board_;
  Eigen::Vector3d light_c_;  // towards the overhead light, unit, in C
  double shadow_length_mm_ = 0.0;
  struct PegBox {
    int u0, v0, u1, v1;
  };
  std::vector<PegBox> peg_boxes_;
  std::vector<float> texture_;  // coarse grid of the lab's texture, -1..1
  int texture_cols_ = 0;

  cv::Mat background_;              // CV_32FC1
  cv::Mat board_level_;             // CV_32FC1
  cv::Mat depth_;                   // CV_32FC1, background range along each pixel's ray
  cv::Mat scene_;                   // CV_32FC1 work buffer
  cv::Mat frame_depth_;             // CV_32FC1 work buffer
  std::vector<float> noise_table_;  // N(0, noise_sigma^2)
  std::mt19937_64 rng_;
};

}  // namespace ephor::catching
