#pragma once
// Low-level vision (RAMBO paper, section 4): from a grey image of the
// polyhedral target to image triples (a corner with two corners joined to it
// by image edges), the input of pose estimation.
//
//   enhancement  the symmetric nearest-neighbour filter (Harwood et al.): of
//                each of the four opposite pairs of 3x3 neighbours, the one
//                closer in value to the centre; their mean with the centre;
//   edges        Sobel gradients of the enhanced image;
//   corners      candidates from OpenCV's Shi-Tomasi corners, kept when a
//                "sector filter" (the paper's term) finds the grey level on
//                a ring around them changing at two or more angles that are
//                not just an opposite pair (an edge); sub-pixel by
//                cornerSubPix;
//   joined       two corners are joined when the gradient across the segment
//                between them is strong along most of it. The paper's CM-2
//                compared the incident edge angles at the two vertices and
//                named this edge-pixel count as the costlier alternative; on
//                a serial machine it is the cheaper and surer one.
// Pixels: origin at the top-left pixel's centre, x right, y down.
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "common/rambo/image_triple.h"

namespace ephor::rambo {

struct ImageFeatureOptions {
  int max_corners = 40;
  double corner_quality = 0.01;       // of the strongest candidate's response
  double min_corner_distance_px = 8;  // between candidates
  double sector_radius_px = 6;        // the sector filter's ring
  double min_sector_step = 12;        // grey levels between ring neighbours at a transition
  double min_edge_length_px = 12;     // shorter segments are not tested
  double end_margin_px = 4;           // samples this far from the corners are skipped
  double min_edge_gradient = 10;      // grey levels per pixel across the segment (Sobel / 4)
  double min_edge_fraction = 0.85;    // of the samples along the segment
};

struct ImageFeatures {
  std::vector<Eigen::Vector2d> corners_px;
  std::vector<std::pair<int, int>> edges;  // joined corners (i < j)
  std::vector<ImageTriple> triples;
  std::string reason;  // why there are no triples, when there are none
};

// The enhancement step alone (exposed for tests): CV_8UC1 in and out.
cv::Mat symmetric_nearest_neighbour(const cv::Mat& grey);

// Throws std::invalid_argument for an empty image or one that is not CV_8UC1.
ImageFeatures extract_image_features(const cv::Mat& grey, const ImageFeatureOptions& options = {});

}  // namespace ephor::rambo
