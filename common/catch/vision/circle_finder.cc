#include "common/catch/vision/circle_finder.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>
#include <stdexcept>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "common/catch/board_file.h"

namespace ephor::catching {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kInf = std::numeric_limits<double>::infinity();

double median(std::vector<double>& v) {
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

std::string window_text(const cv::Rect& r) {
  std::ostringstream s;
  s << "(" << r.x << "," << r.y << ")-(" << r.x + r.width - 1 << "," << r.y + r.height - 1 << ")";
  return s.str();
}

// The board's grey level: the image's 90th percentile (the board is the
// bright part of the scene).
double bright_level(const cv::Mat& frame) {
  int hist[256] = {0};
  for (int y = 0; y < frame.rows; ++y)
    for (int x = 0; x < frame.cols; ++x) ++hist[frame.at<uint8_t>(y, x)];
  const double want = 0.9 * frame.rows * frame.cols;
  double seen = 0.0;
  for (int g = 0; g < 256; ++g) {
    seen += hist[g];
    if (seen >= want) return g;
  }
  return 255.0;
}

void check_frame(const cv::Mat& frame) {
  if (frame.empty()) throw std::invalid_argument("CircleFinder: empty frame");
  if (frame.type() != CV_8UC1)
    throw std::invalid_argument("CircleFinder: needs an 8-bit grey frame (CV_8UC1)");
}

}  // namespace

CircleFinder::CircleFinder(const BoardSpec& board, const CameraIntrinsics& camera,
                           CircleFinderOptions options)
    : board_(board), camera_(camera), options_(std::move(options)), pose_(board, camera) {}

std::vector<CircleFinder::Blob> CircleFinder::dark_round_blobs(const cv::Mat& frame) const {
  // Local board brightness: a max filter wider than the largest circle, run
  // at a quarter of the resolution (the board's shading is smooth).
  constexpr int kShrink = 4;
  cv::Mat small, small_max, board_level;
  cv::resize(frame, small,
             cv::Size(std::max(1, frame.cols / kShrink), std::max(1, frame.rows / kShrink)), 0, 0,
             cv::INTER_AREA);
  const int k = (static_cast<int>(options_.max_diameter_px / kShrink) + 3) | 1;
  cv::dilate(small, small_max, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(k, k)));
  cv::resize(small_max, board_level, frame.size(), 0, 0, cv::INTER_LINEAR);
  cv::Mat threshold, dark;
  board_level.convertTo(threshold, CV_8U, options_.dark_fraction);
  cv::compare(frame, threshold, dark, cv::CMP_LT);
  if (options_.windows) {
    cv::Mat keep = cv::Mat::zeros(frame.size(), CV_8U);
    for (const cv::Rect& w : *options_.windows)
      keep(w & cv::Rect(0, 0, frame.cols, frame.rows)) = 255;
    dark &= keep;
  }
  cv::Mat labels, stats, centroids;
  const int n = cv::connectedComponentsWithStats(dark, labels, stats, centroids, 8, CV_32S);
  // The board is the bright part of the scene: a circle is painted on it, so
  // the ring around a true circle is board-bright. Dark texture off the board
  // (the lab around it) is surrounded by dark. Board level: the image's 90th
  // percentile of grey.
  const double board_grey = bright_level(frame);

  std::vector<Blob> blobs;
  const double min_area = kPi / 4.0 * options_.min_diameter_px * options_.min_diameter_px;
  const double max_area = kPi / 4.0 * options_.max_diameter_px * options_.max_diameter_px;
  const cv::Rect image(0, 0, frame.cols, frame.rows);
  for (int l = 1; l < n; ++l) {
    const double area = stats.at<int>(l, cv::CC_STAT_AREA);
    const cv::Rect box(stats.at<int>(l, cv::CC_STAT_LEFT), stats.at<int>(l, cv::CC_STAT_TOP),
                       stats.at<int>(l, cv::CC_STAT_WIDTH), stats.at<int>(l, cv::CC_STAT_HEIGHT));
    if (area < min_area || area > max_area) continue;
    if (box.x == 0 || box.y == 0 || box.br().x >= frame.cols || box.br().y >= frame.rows) continue;
    // Round: its second moments describe an ellipse of the blob's own area.
    const cv::Mat component = labels(box) == l;
    const cv::Moments m = cv::moments(component, true);
    const double c20 = m.mu20 / m.m00, c02 = m.mu02 / m.m00, c11 = m.mu11 / m.m00;
    const double det = c20 * c02 - c11 * c11;
    if (!(det > 0.0)) continue;
    const double half_trace = (c20 + c02) / 2.0;
    const double root = std::sqrt(std::max(0.0, half_trace * half_trace - det));
    const double axis_ratio = std::sqrt((half_trace - root) / (half_trace + root));
    const double fill = area / (4.0 * kPi * std::sqrt(det));
    if (axis_ratio < options_.min_axis_ratio || std::abs(fill - 1.0) > options_.max_fill_error)
      continue;

    // Sub-pixel centroid from grey-level weights around the component.
    const cv::Rect roi = cv::Rect(box.x - 7, box.y - 7, box.width + 14, box.height + 14) & image;
    const cv::Mat own = labels(roi) == l;
    const cv::Mat kernel = cv::getStructuringElement(cv::MORPH_RECT, cv::Size(3, 3));
    cv::Mat inner, support, outer;
    cv::erode(own, inner, kernel, cv::Point(-1, -1), 2);
    if (cv::countNonZero(inner) == 0) inner = own;
    cv::dilate(own, support, kernel, cv::Point(-1, -1), 2);
    cv::dilate(own, outer, kernel, cv::Point(-1, -1), 6);
    const cv::Mat ring = outer & ~support & ~dark(roi);
    // The board's brightness around the circle as a plane in (x, y): the
    // lighting is uneven (fluorescent bands, vignetting), and a constant
    // level biases the centroid towards the darker side by 0.1-0.2 px.
    const cv::Mat pixels = frame(roi);
    Eigen::Matrix3d ata = Eigen::Matrix3d::Zero();
    Eigen::Vector3d atb = Eigen::Vector3d::Zero();
    int ring_count = 0;
    for (int y = 0; y < roi.height; ++y)
      for (int x = 0; x < roi.width; ++x) {
        if (!ring.at<uint8_t>(y, x)) continue;
        const Eigen::Vector3d a(1.0, x, y);
        ata += a * a.transpose();
        atb += a * static_cast<double>(pixels.at<uint8_t>(y, x));
        ++ring_count;
      }
    if (ring_count < 8) continue;
    if (atb[0] / ring_count < 0.5 * board_grey) continue;  // not on the board
    const Eigen::Vector3d plane = ata.ldlt().solve(atb);
    auto bright_at = [&plane](int x, int y) { return plane[0] + plane[1] * x + plane[2] * y; };
    // The circle's paint reflects a fixed fraction of the same light.
    std::vector<double> ratios;
    for (int y = 0; y < roi.height; ++y)
      for (int x = 0; x < roi.width; ++x)
        if (inner.at<uint8_t>(y, x) && bright_at(x, y) > 1.0)
          ratios.push_back(pixels.at<uint8_t>(y, x) / bright_at(x, y));
    if (ratios.empty()) continue;
    const double dark_ratio = median(ratios);
    if (!(dark_ratio < 0.95)) continue;
    double s0 = 0.0, sx = 0.0, sy = 0.0;
    for (int y = 0; y < roi.height; ++y)
      for (int x = 0; x < roi.width; ++x) {
        if (!support.at<uint8_t>(y, x)) continue;
        const double bright = bright_at(x, y);
        const double w = (bright - pixels.at<uint8_t>(y, x)) / (bright * (1.0 - dark_ratio));
        s0 += w;
        sx += w * (roi.x + x);
        sy += w * (roi.y + y);
      }
    if (!(s0 > 0.0)) continue;
    blobs.push_back({Eigen::Vector2d(sx / s0, sy / s0), s0});
  }
  return blobs;
}

// Three round dark blobs: which circle is missing, and where the other three
// say it is. Each choice of the missing circle and labelling of the three
// blobs is solved by P3P (up to four poses); poses that show the board's
// back or put a circle behind the camera are dropped; the rest are scored by
// how well the circles' projected areas match the blobs' (the centroids fit
// exactly with three points); poses that lay the board over dark parts of
// the image are dropped too. The missing circle is named only when the best
// choice beats every choice of another missing circle by the ambiguity margin.
std::string CircleFinder::missing_circle(const std::vector<Blob>& blobs,
                                         const cv::Mat& frame) const {
  const std::string searched = "looked for dark round blobs in the whole " +
                               std::to_string(camera_.width) + " x " +
                               std::to_string(camera_.height) + " image and found 3";
  cv::Matx33d k(camera_.fx, 0.0, camera_.cx, 0.0, camera_.fy, camera_.cy, 0.0, 0.0, 1.0);
  // The board, wholly in view (the paper's one constraint on the camera), is
  // bright where it is not painted: a pose that lays it over the dark lab is
  // wrong. Sample points on a grid of the board, clear of the circles.
  const double bright = 0.6 * bright_level(frame);
  std::vector<Eigen::Vector3d> samples;
  for (int i = 1; i < 8; ++i)
    for (int j = 1; j < 12; ++j) {
      const Eigen::Vector3d p(board_.width_mm * i / 8.0, board_.height_mm * j / 12.0, 0.0);
      bool clear = true;
      for (const BoardCircle& c : board_.circles)
        if (std::hypot(p.x() - c.x_mm, p.y() - c.y_mm) < c.diameter_mm) clear = false;
      if (clear) samples.push_back(p);
    }
  auto board_seen_bright = [&](const Pose& pose) {
    int dark = 0;
    for (const Eigen::Vector3d& p : samples) {
      const Eigen::Vector2d px = pose_.project(pose, p);
      const int u = static_cast<int>(std::lround(px.x())),
                v = static_cast<int>(std::lround(px.y()));
      if (!px.allFinite() || u < 0 || v < 0 || u >= frame.cols || v >= frame.rows ||
          frame.at<uint8_t>(v, u) < bright)
        ++dark;
    }
    // Pegs and shadows darken a few samples.
    return dark <= static_cast<int>(samples.size()) / 5;
  };
  std::array<double, 4> best_per_missing;
  best_per_missing.fill(kInf);
  std::array<Eigen::Vector2d, 4> where{};
  for (int missing = 0; missing < 4; ++missing) {
    std::array<int, 3> present{};
    for (int i = 0, j = 0; i < 4; ++i)
      if (i != missing) present[static_cast<size_t>(j++)] = i;
    std::vector<cv::Point3d> object;
    for (int i : present) {
      const BoardCircle& c = board_.circles[static_cast<size_t>(i)];
      object.emplace_back(c.x_mm, c.y_mm, 0.0);
    }
    std::array<int, 3> perm{0, 1, 2};
    do {
      std::vector<cv::Point2d> image;
      for (int b : perm) {
        const Eigen::Vector2d& c = blobs[static_cast<size_t>(b)].centroid;
        image.emplace_back(c.x(), c.y());
      }
      std::vector<cv::Mat> rvecs, tvecs;
      try {
        cv::solveP3P(object, image, k, camera_.distortion, rvecs, tvecs, cv::SOLVEPNP_P3P);
      } catch (const cv::Exception&) {
        continue;  // degenerate (collinear) blobs
      }
      for (size_t s = 0; s < rvecs.size(); ++s) {
        cv::Matx33d r;
        cv::Rodrigues(rvecs[s], r);
        Pose pose = Pose::Identity();
        for (int i = 0; i < 3; ++i) {
          for (int j = 0; j < 3; ++j) pose.linear()(i, j) = r(i, j);
          pose.translation()(i) = tvecs[s].at<double>(i);
        }
        // The face is seen (the camera on +z of B) and every circle is in front.
        const Eigen::Vector3d camera_in_b = -pose.linear().transpose() * pose.translation();
        if (!(camera_in_b.z() > 0.0)) continue;
        if (!board_seen_bright(pose)) continue;
        double score = 0.0;
        for (size_t i = 0; i < 3 && std::isfinite(score); ++i) {
          const ProjectedCircle pc = pose_.project_circle(pose, present[i]);
          if (!(pc.area_px > 0.0)) {
            score = kInf;
            break;
          }
          const double a = std::log(blobs[static_cast<size_t>(perm[i])].area / pc.area_px) /
                           options_.area_sigma_log;
          score += a * a;
        }
        if (!((pose * Eigen::Vector3d(board_.circles[static_cast<size_t>(missing)].x_mm,
                                      board_.circles[static_cast<size_t>(missing)].y_mm, 0.0))
                  .z() > 0.0))
          score = kInf;
        if (score < best_per_missing[static_cast<size_t>(missing)]) {
          best_per_missing[static_cast<size_t>(missing)] = score;
          where[static_cast<size_t>(missing)] = pose_.project(
              pose, Eigen::Vector3d(board_.circles[static_cast<size_t>(missing)].x_mm,
                                    board_.circles[static_cast<size_t>(missing)].y_mm, 0.0));
        }
      }
    } while (std::next_permutation(perm.begin(), perm.end()));
  }
  std::array<int, 4> order{0, 1, 2, 3};
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return best_per_missing[static_cast<size_t>(a)] < best_per_missing[static_cast<size_t>(b)];
  });
  const double best = best_per_missing[static_cast<size_t>(order[0])];
  const double next = best_per_missing[static_cast<size_t>(order[1])];
  auto at = [&](int i) {
    std::ostringstream t;
    t.setf(std::ios::fixed);
    t.precision(0);
    t << "(" << where[static_cast<size_t>(i)].x() << ", " << where[static_cast<size_t>(i)].y()
      << ") px";
    return t.str();
  };
  if (!std::isfinite(best) || next - best < options_.ambiguity_margin) {
    std::string candidates;
    for (int i : order)
      if (best_per_missing[static_cast<size_t>(i)] - best < options_.ambiguity_margin)
        candidates += std::string(candidates.empty() ? "" : " or ") + "the " + circle_name(i) +
                      " at " + at(i);
    return "a circle not found (" +
           (candidates.empty() ? std::string("which one cannot be told") : candidates) +
           "): " + searched + ", need 4";
  }
  const int m = order[0];
  const Eigen::Vector2d& p = where[static_cast<size_t>(m)];
  const bool inside = p.x() >= -0.5 && p.y() >= -0.5 && p.x() <= camera_.width - 0.5 &&
                      p.y() <= camera_.height - 0.5;
  std::ostringstream msg;
  msg.setf(std::ios::fixed);
  msg.precision(0);
  msg << "circle " << circle_name(m) << " not found: " << searched
      << "; the other three put it at (" << p.x() << ", " << p.y() << ") px"
      << (inside ? ", in the image (covered, or not dark enough?)" : ", outside the image");
  return msg.str();
}

CircleFinderResult CircleFinder::label(const std::vector<Blob>& blobs, const cv::Mat& frame) const {
  CircleFinderResult out;
  out.blobs_seen = static_cast<int>(blobs.size());
  if (options_.windows) {
    for (int i = 0; i < 4; ++i) {
      const cv::Rect& w = (*options_.windows)[static_cast<size_t>(i)];
      const Blob* best = nullptr;
      for (const Blob& b : blobs)
        if (w.contains(cv::Point2d(b.centroid.x(), b.centroid.y())) &&
            (best == nullptr || b.area > best->area))
          best = &b;
      if (best == nullptr) {
        out.problem = std::string("circle ") + circle_name(i) + " not found: looked in window " +
                      window_text(w);
        return out;
      }
      out.circles[static_cast<size_t>(i)].centroid_px = best->centroid;
      out.circles[static_cast<size_t>(i)].area_px = best->area;
    }
    out.found = true;
    out.runner_up_score = kInf;
    return out;
  }
  if (blobs.size() == 3) {
    out.problem = missing_circle(blobs, frame);
    return out;
  }
  if (blobs.size() < 4) {
    out.problem = "found " + std::to_string(blobs.size()) + " dark round blob" +
                  (blobs.size() == 1 ? "" : "s") + " in the whole " +
                  std::to_string(camera_.width) + " x " + std::to_string(camera_.height) +
                  " image, need 4";
    return out;
  }
  // The largest eight at most: 70 sets of four, 24 labellings each.
  std::vector<Blob> pool = blobs;
  std::sort(pool.begin(), pool.end(), [](const Blob& a, const Blob& b) { return a.area > b.area; });
  if (pool.size() > 8) pool.resize(8);
  const int n = static_cast<int>(pool.size());
  double best = kInf, runner_up = kInf;
  std::array<int, 4> best_labelling{};
  std::vector<bool> pick(static_cast<size_t>(n), false);
  std::fill(pick.begin(), pick.begin() + 4, true);
  do {
    std::array<int, 4> chosen{};
    for (int i = 0, j = 0; i < n; ++i)
      if (pick[static_cast<size_t>(i)]) chosen[static_cast<size_t>(j++)] = i;
    std::array<int, 4> perm = chosen;
    std::sort(perm.begin(), perm.end());
    do {
      std::array<Eigen::Vector2d, 4> c;
      for (size_t i = 0; i < 4; ++i) c[i] = pool[static_cast<size_t>(perm[i])].centroid;
      const BoardPoseResult pose = pose_.estimate(c, {PnpMethod::kIppe, 0});
      if (!pose.ok) continue;
      double score = 0.0;
      for (size_t i = 0; i < 4; ++i) {
        const ProjectedCircle pc = pose_.project_circle(pose.board_to_camera, static_cast<int>(i));
        if (!(pc.area_px > 0.0)) {
          score = kInf;
          break;
        }
        const double e = (pc.centroid_px - c[i]).norm() / options_.centroid_sigma_px;
        const double a = std::log(pool[static_cast<size_t>(perm[i])].area / pc.area_px) /
                         options_.area_sigma_log;
        score += e * e + a * a;
      }
      if (score < best) {
        runner_up = best;
        best = score;
        best_labelling = perm;
      } else if (score < runner_up) {
        runner_up = score;
      }
    } while (std::next_permutation(perm.begin(), perm.end()));
  } while (std::prev_permutation(pick.begin(), pick.end()));

  out.labelling_score = best;
  out.runner_up_score = runner_up;
  if (!std::isfinite(best)) {
    out.problem = "found " + std::to_string(blobs.size()) +
                  " dark round blobs but no labelling of four of them fits the board";
    return out;
  }
  if (runner_up - best < options_.ambiguity_margin) {
    std::ostringstream s;
    s << "cannot tell the four circles apart: the best labelling scores " << best << ", the next "
      << runner_up << " (give windows of interest, or make one circle clearly larger)";
    out.problem = s.str();
    return out;
  }
  for (size_t i = 0; i < 4; ++i) {
    out.circles[i].centroid_px = pool[static_cast<size_t>(best_labelling[i])].centroid;
    out.circles[i].area_px = pool[static_cast<size_t>(best_labelling[i])].area;
  }
  out.found = true;
  return out;
}

CircleFinderResult CircleFinder::find(const cv::Mat& frame) const {
  check_frame(frame);
  CircleFinderResult r = label(dark_round_blobs(frame), frame);
  r.frames_used = r.found ? 1 : 0;
  return r;
}

CircleFinderResult CircleFinder::find(const std::vector<cv::Mat>& frames) const {
  if (frames.empty()) throw std::invalid_argument("CircleFinder: no frames");
  std::vector<CircleFinderResult> good;
  CircleFinderResult first_failure;
  bool failed = false;
  for (const cv::Mat& f : frames) {
    CircleFinderResult r = find(f);
    if (r.found) {
      good.push_back(std::move(r));
    } else if (!failed) {
      first_failure = std::move(r);
      failed = true;
    }
  }
  if (good.size() * 2 <= frames.size() && failed) {
    first_failure.problem += " (in " + std::to_string(frames.size() - good.size()) + " of " +
                             std::to_string(frames.size()) + " frames)";
    return first_failure;
  }
  CircleFinderResult out = good.front();
  out.frames_used = static_cast<int>(good.size());
  const double n = static_cast<double>(good.size());
  for (size_t i = 0; i < 4; ++i) {
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    double area = 0.0;
    for (const auto& g : good) {
      mean += g.circles[i].centroid_px / n;
      area += g.circles[i].area_px / n;
    }
    double spread = 0.0;
    for (const auto& g : good) spread += (g.circles[i].centroid_px - mean).squaredNorm() / n;
    out.circles[i] = {mean, area, std::sqrt(spread)};
  }
  return out;
}

std::array<cv::Rect, 4> parse_circle_windows(const std::string& text) {
  std::array<cv::Rect, 4> out;
  std::stringstream ss(text);
  std::string item;
  int i = 0;
  while (std::getline(ss, item, ';')) {
    int u0 = 0, v0 = 0, u1 = 0, v1 = 0;
    char c1 = 0, c2 = 0, c3 = 0;
    std::stringstream is(item);
    if (i >= 4 || !(is >> u0 >> c1 >> v0 >> c2 >> u1 >> c3 >> v1) || c1 != ',' || c2 != ',' ||
        c3 != ',' || u1 <= u0 || v1 <= v0)
      throw std::invalid_argument("circle windows: want four 'u0,v0,u1,v1' (u1 > u0, v1 > v0) " +
                                  std::string("separated by ';', got '") + text + "'");
    out[static_cast<size_t>(i++)] = cv::Rect(u0, v0, u1 - u0 + 1, v1 - v0 + 1);
  }
  if (i != 4)
    throw std::invalid_argument("circle windows: want 4 windows, got " + std::to_string(i) +
                                " in '" + text + "'");
  return out;
}

}  // namespace ephor::catching
