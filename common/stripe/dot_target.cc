#include "common/stripe/dot_target.h"

#include <algorithm>
#include <cmath>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "common/stripe/sensor_calibrator.h"

namespace ephor::stripe {

DotTarget::DotTarget(Eigen::Vector2d spot_mm, DotTargetLayout layout)
    : spot_mm_(spot_mm), layout_(layout) {}

Eigen::Isometry3d DotTarget::target_in_table() const {
  return Eigen::Isometry3d(Eigen::Translation3d(spot_mm_.x(), spot_mm_.y(), 0.0));
}

std::vector<Eigen::Vector3d> DotTarget::dots_in_target() const {
  std::vector<Eigen::Vector3d> out;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      if (r != 1 || c != 1)
        out.emplace_back((c - 1) * layout_.pitch_mm, (r - 1) * layout_.pitch_mm, 0.0);
  return out;
}

std::vector<Eigen::Vector2d> DotTarget::dots_in_table() const {
  std::vector<Eigen::Vector2d> out;
  const Eigen::Isometry3d t = target_in_table();
  for (const Eigen::Vector3d& p : dots_in_target()) out.push_back((t * p).head<2>());
  return out;
}

std::vector<double> DotTarget::dot_radii_mm() const {
  std::vector<double> out(8, layout_.dot_radius_mm);
  out[0] = layout_.marker_radius_mm;
  return out;
}

std::optional<TargetSighting> DotTarget::find(const cv::Mat& image, const CameraIntrinsics& camera,
                                              int threshold, double max_rms_px) const {
  if (image.empty() || image.type() != CV_8UC1) return std::nullopt;
  const auto spot = find_spot(image, threshold);
  if (!spot) return std::nullopt;

  cv::Mat labels, stats, centroids;
  const cv::Mat dark = image < threshold;
  const int n = cv::connectedComponentsWithStats(dark, labels, stats, centroids, 8, CV_32S);
  // Blobs by area, largest first: the spot, the marker, the dots; noise
  // (under 3 px) left out.
  std::vector<int> blobs;
  for (int i = 1; i < n; ++i)
    if (stats.at<int>(i, cv::CC_STAT_AREA) >= 3) blobs.push_back(i);
  if (blobs.size() != 9) return std::nullopt;
  std::sort(blobs.begin(), blobs.end(), [&](int a, int b) {
    return stats.at<int>(a, cv::CC_STAT_AREA) > stats.at<int>(b, cv::CC_STAT_AREA);
  });
  // The marker is 2.6 times a dot's area; perspective changes the dots'
  // areas by up to about 1.4 across the target.
  if (stats.at<int>(blobs[1], cv::CC_STAT_AREA) < 1.7 * stats.at<int>(blobs[2], cv::CC_STAT_AREA))
    return std::nullopt;
  // Each dot's darkness-weighted centroid over its box grown by 2 px
  // (pixels of other blobs left out), as find_spot weighs the spot's.
  std::vector<cv::Point2f> points;  // the marker first, then the dots, then the spot
  const double bright = 170.0;
  for (size_t b = 1; b < blobs.size(); ++b) {
    const int i = blobs[b];
    const int x = stats.at<int>(i, cv::CC_STAT_LEFT), y = stats.at<int>(i, cv::CC_STAT_TOP);
    const int w = stats.at<int>(i, cv::CC_STAT_WIDTH), h = stats.at<int>(i, cv::CC_STAT_HEIGHT);
    if (x <= 0 || y <= 0 || x + w >= image.cols || y + h >= image.rows) return std::nullopt;
    double sw = 0, su = 0, sv = 0;
    for (int v = std::max(0, y - 2); v < std::min(image.rows, y + h + 2); ++v)
      for (int u = std::max(0, x - 2); u < std::min(image.cols, x + w + 2); ++u) {
        const int l = labels.at<int>(v, u);
        if (l != 0 && l != i) continue;
        const double wgt = std::max(0.0, bright - image.at<unsigned char>(v, u));
        sw += wgt;
        su += wgt * u;
        sv += wgt * v;
      }
    if (!(sw > 0)) return std::nullopt;
    points.emplace_back(static_cast<float>(su / sw), static_cast<float>(sv / sw));
  }
  points.emplace_back(static_cast<float>(spot->x()), static_cast<float>(spot->y()));

  // The 3 x 3 grid's order (the spot its centre) from the centroids: no
  // blob detector, the points are given; clustering, as the default search
  // fails on so few points seen in perspective.
  std::vector<cv::Point2f> ordered;
  if (!cv::findCirclesGrid(cv::Mat(points), cv::Size(3, 3), ordered,
                           cv::CALIB_CB_SYMMETRIC_GRID | cv::CALIB_CB_CLUSTERING,
                           cv::Ptr<cv::FeatureDetector>()) ||
      ordered.size() != 9 || cv::norm(ordered[4] - points.back()) > 1e-3)
    return std::nullopt;
  // Its order is the layout's up to a turn or a flip: the one with the
  // marker at column 0, row 0 and the handedness of a view from above (the
  // images of the table's +x and +y turn clockwise, as the image's v runs
  // down: their cross product is negative).
  std::vector<cv::Point2f> best;
  for (int t = 0; t < 8 && best.empty(); ++t) {
    std::vector<cv::Point2f> at(9);  // image point of grid position (col, row)
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) {
        int cc = c - 1, rr = r - 1;  // about the centre
        if (t & 4) std::swap(cc, rr);
        if (t & 1) cc = -cc;
        if (t & 2) rr = -rr;
        at[static_cast<size_t>((rr + 1) * 3 + cc + 1)] = ordered[static_cast<size_t>(r * 3 + c)];
      }
    if (cv::norm(at[0] - points[0]) > 1e-3) continue;
    const cv::Point2f ax = at[5] - at[3], ay = at[7] - at[1];
    if (ax.x * ay.y - ax.y * ay.x >= 0.0f) continue;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c)
        if (r != 1 || c != 1) best.push_back(at[static_cast<size_t>(r * 3 + c)]);
  }
  if (best.size() != 8) return std::nullopt;

  const std::vector<Eigen::Vector3d> object = dots_in_target();
  std::vector<cv::Point3f> object_cv;
  for (const Eigen::Vector3d& p : object)
    object_cv.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()), 0.0f);
  const cv::Matx33d k(camera.fx_px, 0, camera.cx_px, 0, camera.fy_px, camera.cy_px, 0, 0, 1);
  cv::Mat rvec, tvec;
  if (!cv::solvePnP(object_cv, best, k, cv::noArray(), rvec, tvec, false, cv::SOLVEPNP_IPPE))
    return std::nullopt;
  cv::solvePnPRefineLM(object_cv, best, k, cv::noArray(), rvec, tvec);
  std::vector<cv::Point2f> back;
  cv::projectPoints(object_cv, rvec, tvec, k, cv::noArray(), back);
  double ss = 0.0;
  for (size_t i = 0; i < best.size(); ++i) {
    const cv::Point2f d = back[i] - best[i];
    ss += static_cast<double>(d.dot(d));
  }
  TargetSighting out;
  out.rms_px = std::sqrt(ss / static_cast<double>(best.size()));
  if (!(out.rms_px <= max_rms_px)) return std::nullopt;
  cv::Matx33d rot;
  cv::Rodrigues(rvec, rot);
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) out.target_in_camera.linear()(i, j) = rot(i, j);
    out.target_in_camera.translation()(i) = tvec.at<double>(i);
  }
  for (const cv::Point2f& p : best) out.dots_px.emplace_back(p.x, p.y);
  out.spot_px = *spot;
  return out;
}

}  // namespace ephor::stripe
