#include "common/rambo/image_features.h"

#include <cmath>
#include <cstdlib>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

namespace ephor::rambo {

cv::Mat symmetric_nearest_neighbour(const cv::Mat& grey) {
  if (grey.empty() || grey.type() != CV_8UC1)
    throw std::invalid_argument("symmetric_nearest_neighbour: want a non-empty 8-bit grey image");
  cv::Mat out = grey.clone();
  // Opposite pairs of the 3x3 neighbourhood: (dy, dx) and (-dy, -dx).
  static const int kPairs[4][2] = {{-1, -1}, {-1, 0}, {-1, 1}, {0, -1}};
  for (int y = 1; y < grey.rows - 1; ++y) {
    const uint8_t* rows[3] = {grey.ptr<uint8_t>(y - 1), grey.ptr<uint8_t>(y),
                              grey.ptr<uint8_t>(y + 1)};
    uint8_t* o = out.ptr<uint8_t>(y);
    for (int x = 1; x < grey.cols - 1; ++x) {
      const int c = rows[1][x];
      int sum = c;
      for (const auto& p : kPairs) {
        const int a = rows[1 + p[0]][x + p[1]];
        const int b = rows[1 - p[0]][x - p[1]];
        sum += std::abs(a - c) <= std::abs(b - c) ? a : b;
      }
      o[x] = static_cast<uint8_t>((sum + 2) / 5);
    }
  }
  return out;
}

ImageFeatures extract_image_features(const cv::Mat& grey, const ImageFeatureOptions& o) {
  if (grey.empty() || grey.type() != CV_8UC1)
    throw std::invalid_argument("extract_image_features: want a non-empty 8-bit grey image");
  ImageFeatures f;
  const cv::Mat enhanced = symmetric_nearest_neighbour(grey);
  // Candidates: Shi-Tomasi corners, many and weak (interior vertices between
  // faces of similar shade respond far less than the silhouette's).
  cv::Mat smooth;
  cv::GaussianBlur(enhanced, smooth, cv::Size(0, 0), 1.0);
  std::vector<cv::Point2f> candidates;
  cv::goodFeaturesToTrack(smooth, candidates, 4 * o.max_corners, o.corner_quality,
                          o.min_corner_distance_px);
  // The sector filter: around a vertex the grey level changes at two or more
  // angles that are not opposite; along a straight edge (where rasterised
  // silhouettes also give corner responses) at two opposite ones.
  std::vector<cv::Point2f> corners;
  for (const auto& cand : candidates) {
    const double px_x = static_cast<double>(cand.x), px_y = static_cast<double>(cand.y);
    constexpr int kSamples = 48;
    const double r = o.sector_radius_px;
    if (px_x < r + 1 || px_y < r + 1 || px_x > smooth.cols - r - 2 || px_y > smooth.rows - r - 2)
      continue;
    double ring[kSamples];
    for (int k = 0; k < kSamples; ++k) {
      const double a = 2.0 * M_PI * k / kSamples;
      cv::Mat px;
      cv::getRectSubPix(smooth, cv::Size(1, 1),
                        cv::Point2f(static_cast<float>(px_x + r * std::cos(a)),
                                    static_cast<float>(px_y + r * std::sin(a))),
                        px, CV_32F);
      ring[k] = static_cast<double>(px.at<float>(0, 0));
    }
    // Transitions: local maxima of the change between neighbours on the ring.
    double diff[kSamples];
    for (int k = 0; k < kSamples; ++k)
      diff[k] = std::abs(ring[(k + 1) % kSamples] - ring[(k + kSamples - 1) % kSamples]);
    std::vector<int> jumps;
    for (int k = 0; k < kSamples; ++k)
      if (diff[k] >= o.min_sector_step && diff[k] >= diff[(k + 1) % kSamples] &&
          diff[k] > diff[(k + kSamples - 1) % kSamples])
        jumps.push_back(k);
    if (jumps.size() < 2) continue;
    bool opposite_pair_only = jumps.size() == 2;
    if (opposite_pair_only) {
      const int d = std::abs(jumps[0] - jumps[1]);
      opposite_pair_only = std::abs(std::min(d, kSamples - d) - kSamples / 2) <= kSamples / 12;
    }
    if (opposite_pair_only) continue;
    corners.push_back(cand);
    if (static_cast<int>(corners.size()) >= o.max_corners) break;
  }
  if (corners.size() < 3) {
    f.reason = "fewer than 3 corners in the image (" + std::to_string(corners.size()) + ")";
    for (const auto& c : corners) f.corners_px.emplace_back(c.x, c.y);
    return f;
  }
  cv::cornerSubPix(smooth, corners, cv::Size(4, 4), cv::Size(-1, -1),
                   cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 20, 0.03));
  for (const auto& c : corners) f.corners_px.emplace_back(c.x, c.y);
  cv::Mat gx, gy;
  cv::Sobel(enhanced, gx, CV_32F, 1, 0, 3, 0.25);
  cv::Sobel(enhanced, gy, CV_32F, 0, 1, 3, 0.25);
  const int n = static_cast<int>(f.corners_px.size());
  std::vector<std::vector<int>> joined(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      const Eigen::Vector2d a = f.corners_px[static_cast<std::size_t>(i)];
      const Eigen::Vector2d b = f.corners_px[static_cast<std::size_t>(j)];
      const double len = (b - a).norm();
      if (len < o.min_edge_length_px) continue;
      const Eigen::Vector2d dir = (b - a) / len;
      const Eigen::Vector2d normal(-dir.y(), dir.x());
      int samples = 0, strong = 0;
      for (double s = o.end_margin_px; s <= len - o.end_margin_px; s += 1.0) {
        const Eigen::Vector2d p = a + s * dir;
        const int x = static_cast<int>(std::lround(p.x())),
                  y = static_cast<int>(std::lround(p.y()));
        if (x < 1 || y < 1 || x >= grey.cols - 1 || y >= grey.rows - 1) continue;
        ++samples;
        // The strongest gradient across the segment within a pixel of it.
        double best = 0.0;
        for (int k = -1; k <= 1; ++k) {
          const int xx = static_cast<int>(std::lround(p.x() + k * normal.x()));
          const int yy = static_cast<int>(std::lround(p.y() + k * normal.y()));
          const double g = std::abs(static_cast<double>(gx.at<float>(yy, xx)) * normal.x() +
                                    static_cast<double>(gy.at<float>(yy, xx)) * normal.y());
          best = std::max(best, g);
        }
        strong += best >= o.min_edge_gradient ? 1 : 0;
      }
      if (samples > 0 && strong >= o.min_edge_fraction * samples) {
        f.edges.emplace_back(i, j);
        joined[static_cast<std::size_t>(i)].push_back(j);
        joined[static_cast<std::size_t>(j)].push_back(i);
      }
    }
  }
  for (int r = 0; r < n; ++r) {
    const auto& nb = joined[static_cast<std::size_t>(r)];
    for (std::size_t u = 0; u < nb.size(); ++u)
      for (std::size_t v = u + 1; v < nb.size(); ++v) {
        ImageTriple t;
        t.reference_px = f.corners_px[static_cast<std::size_t>(r)];
        t.a_px = f.corners_px[static_cast<std::size_t>(nb[u])];
        t.b_px = f.corners_px[static_cast<std::size_t>(nb[v])];
        f.triples.push_back(t);
      }
  }
  if (f.triples.empty()) f.reason = "no corner has two corners joined to it by edges";
  return f;
}

}  // namespace ephor::rambo
