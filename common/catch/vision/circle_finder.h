#pragma once
// CircleFinder: the initialisation of paper 000, section 3. Finds the image
// centroids of the board's four black circles, automatically or inside the
// operator's windows of interest (the paper's mask), for BoardPoseEstimator.
//
// Per frame: a pixel is dark when it is below dark_fraction of the local
// board brightness (a max filter as wide as the largest circle); dark pixels
// are grouped into connected components and round blobs of plausible size
// are kept. Each blob's centroid is the zeroth and first moments (paper eqs
// 2-3) of grey-level weights w = (board - I) / (board - circle), board and
// circle levels taken around and inside the blob, so edge pixels count by
// how much of them the circle covers: sub-pixel accuracy. Over several
// frames the per-frame centroids are averaged (the paper kept the reading of
// largest area out of 10).
//
// Which blob is which circle: with windows, the window says so. Without,
// every labelling of the blobs as top-left .. bottom-right is scored by how
// well its IPPE pose explains the blob centroids and areas (the default
// board's top-left circle is larger than the others); if the best and the
// next-best labelling score alike, the finder says it cannot tell them apart.
//
// Expected failures (no circles, covered circle, ambiguity) are a status with
// a message that says where the circles were looked for: a window named per
// circle, or the whole image. With three blobs in the whole image, the
// missing circle is named with where the other three put it (P3P on each
// choice, scored by the blobs' sizes and a bright board around them), or
// the two or more it cannot be told from are. Bad arguments throw
// std::invalid_argument. Immutable; safe to
// share between threads.

#include <array>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "common/catch/board_model.h"
#include "common/catch/vision/board_pose_estimator.h"

namespace ephor::catching {

struct CircleFinderOptions {
  double dark_fraction = 0.6;    // dark: below this fraction of the local board brightness
  double min_diameter_px = 6.0;  // plausible blob sizes (equivalent-disc diameter)
  double max_diameter_px = 120.0;
  double min_axis_ratio = 0.2;  // minor / major axis of a blob's ellipse (oblique views)
  double max_fill_error = 0.2;  // |area / area of its moment ellipse - 1|
  // The operator's windows of interest, one per circle in board order; all
  // four or none. Only pixels inside the windows are looked at.
  std::optional<std::array<cv::Rect, 4>> windows;
  // How much better (in score units, ~ chi-square) the best labelling must
  // be than the next to be trusted.
  double ambiguity_margin = 9.0;
  double centroid_sigma_px = 0.5;  // scoring: expected centroid misfit
  double area_sigma_log = 0.15;    // scoring: expected log area misfit
};

struct CircleImage {
  Eigen::Vector2d centroid_px = Eigen::Vector2d::Zero();  // (u, v)
  double area_px = 0.0;    // zeroth moment of the grey-level weights, px^2
  double spread_px = 0.0;  // RMS distance of the per-frame centroids from their mean
};

struct CircleFinderResult {
  bool found = false;
  std::string problem;                   // why not found
  std::array<CircleImage, 4> circles{};  // board order
  int frames_used = 0;
  int blobs_seen = 0;  // round dark blobs in the (first) frame
  // Labelling scores (lower is better); runner-up is +inf when only one
  // labelling was physically possible or windows were given.
  double labelling_score = 0.0;
  double runner_up_score = 0.0;
};

class CircleFinder {
 public:
  CircleFinder(const BoardSpec& board, const CameraIntrinsics& camera,
               CircleFinderOptions options = {});

  // One 8-bit grey frame. Throws std::invalid_argument on an empty or non-8-bit frame.
  CircleFinderResult find(const cv::Mat& frame) const;
  // Several frames of a still scene: per-frame readings averaged (frames
  // that fail are skipped; more than half failing fails with the first
  // frame's problem).
  CircleFinderResult find(const std::vector<cv::Mat>& frames) const;

 private:
  struct Blob {
    Eigen::Vector2d centroid;
    double area = 0.0;
  };
  std::vector<Blob> dark_round_blobs(const cv::Mat& frame) const;
  CircleFinderResult label(const std::vector<Blob>& blobs, const cv::Mat& frame) const;
  // With three blobs: which circle is missing and where, or that it cannot be told.
  std::string missing_circle(const std::vector<Blob>& blobs, const cv::Mat& frame) const;

  BoardSpec board_;
  CameraIntrinsics camera_;
  CircleFinderOptions options_;
  BoardPoseEstimator pose_;
};

// The operator's four windows as written on a command line:
// "u0,v0,u1,v1;u0,v0,u1,v1;..." (top-left, top-right, bottom-left,
// bottom-right; inclusive corners, px). Throws std::invalid_argument naming
// what is wrong with `text`.
std::array<cv::Rect, 4> parse_circle_windows(const std::string& text);

}  // namespace ephor::catching
