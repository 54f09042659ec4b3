#pragma once
// Shared set-ups of the catch vision tests and benchmark.

#include <vector>

#include <opencv2/core.hpp>

#include "common/catch/vision/synthetic_board.h"

namespace ephor::catching::testing {

inline SyntheticScene board_scene(double distance_mm, double tilt_deg, double pan_deg = 0.0,
                                  double roll_deg = 0.0) {
  SyntheticScene s;
  s.board_to_camera = look_at_board(s.board, distance_mm, tilt_deg, pan_deg, roll_deg);
  return s;
}

// `n` frames of the same scene with independent noise.
inline std::vector<cv::Mat> noisy_frames(const SyntheticScene& s, int n, double sigma,
                                         uint64_t seed) {
  std::vector<cv::Mat> out;
  for (int i = 0; i < n; ++i)
    out.push_back(render_board(s, sigma, seed + static_cast<uint64_t>(i)));
  return out;
}

}  // namespace ephor::catching::testing
