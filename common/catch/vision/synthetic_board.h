#pragma once
// Synthetic camera images of the catching board for tests and benchmarks:
// the board plane with its four dark circles seen through a pinhole camera
// (no lens distortion), ray-cast per pixel to the board face z_B = 0, and a
// ball (a sphere of the board's ball diameter resting on the face, centre at
// z_B = +radius) slightly brighter or darker than the board. Pixels whose
// four corners see different things are supersampled, so edges are
// anti-aliased as a real sensor integrates them. Noise is Gaussian with a
// fixed seed.

#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "common/catch/board_model.h"

namespace ephor::catching {

struct SyntheticBall {
  Eigen::Vector2d xy_b_mm{300.0, 450.0};  // where the ball touches the board, B
  double contrast = 5.0;                  // ball grey minus board grey (either sign)
};

struct SyntheticScene {
  BoardSpec board;
  CameraIntrinsics camera;                  // its distortion is ignored
  Pose board_to_camera = Pose::Identity();  // p_C = R p_B + t
  double board_grey = 170.0;
  double circle_grey = 25.0;
  double background_grey = 80.0;     // off the board
  std::vector<int> covered_circles;  // circles painted over (board grey)
  std::optional<SyntheticBall> ball;
  int edge_supersample = 8;  // n x n samples in a pixel on an edge
};

// The scene as an 8-bit image (camera.width x camera.height), with Gaussian
// noise of `noise_sigma` grey levels drawn from `seed`, rounded and clamped.
cv::Mat render_board(const SyntheticScene& scene, double noise_sigma = 0.0, uint64_t seed = 1);

// A camera `distance_mm` from the board's centre on the face side, looking at
// the centre, the view tilted by `tilt_deg` away from the board's normal
// (towards +y of B, down the slope), turned by `pan_deg` about the board's
// normal and rolled by `roll_deg` about the optical axis. At zero tilt and
// roll the board's top is at the top of the image (and B's x runs to the left).
Pose look_at_board(const BoardSpec& board, double distance_mm, double tilt_deg,
                   double pan_deg = 0.0, double roll_deg = 0.0);

// Ideal pinhole projection (px) of a point of B.
Eigen::Vector2d project_pinhole(const CameraIntrinsics& camera, const Pose& board_to_camera,
                                const Eigen::Vector3d& p_b_mm);

}  // namespace ephor::catching
