#include "common/catch/vision/motion_centroid.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include <opencv2/imgproc.hpp>
#include <opencv2/video/background_segm.hpp>

namespace ephor::catching {
namespace {

constexpr double kPi = 3.14159265358979323846;

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

cv::Rect clip_window(const std::optional<cv::Rect>& window, const cv::Size& size) {
  const cv::Rect image(0, 0, size.width, size.height);
  return window ? (*window & image) : image;
}

void check(const cv::Mat& frame, const cv::Mat& previous) {
  if (frame.empty() || frame.type() != CV_8UC1)
    throw std::invalid_argument("motion: needs a non-empty 8-bit grey frame (CV_8UC1)");
  if (!previous.empty() && previous.size() != frame.size())
    throw std::invalid_argument("motion: frame size changed");
}

// Area of the lens where two discs of radius r, d apart, overlap.
double lens_area(double d, double r) {
  if (d >= 2.0 * r) return 0.0;
  return 2.0 * r * r * std::acos(d / (2.0 * r)) - 0.5 * d * std::sqrt(4.0 * r * r - d * d);
}

struct Moments {
  double n = 0.0, sx = 0.0, sy = 0.0;      // binary
  double w = 0.0, wx = 0.0, wy = 0.0;      // weighted by |difference|
  double sxx = 0.0, syy = 0.0, sxy = 0.0;  // binary, second (refine() only)
  Eigen::Vector2d weighted() const { return {wx / w, wy / w}; }
  // Minor / major axis of the binary part's moment ellipse (1: round).
  double axis_ratio() const {
    if (n < 3.0) return 0.0;
    const double mx = sx / n, my = sy / n;
    const double a = sxx / n - mx * mx, c = syy / n - my * my, b = sxy / n - mx * my;
    const double h = 0.5 * (a + c), r = std::sqrt(std::max(0.0, 0.25 * (a - c) * (a - c) + b * b));
    return h + r > 0.0 ? std::sqrt(std::max(0.0, h - r) / (h + r)) : 0.0;
  }
};

// Moments of one sign of the difference (sign * d >= th) inside `box`.
Moments part_moments(const cv::Mat& cur, const cv::Mat& old, const cv::Rect& box, int sign,
                     int th) {
  Moments m;
  for (int y = box.y; y < box.br().y; ++y) {
    const uint8_t* a = cur.ptr<uint8_t>(y);
    const uint8_t* b = old.ptr<uint8_t>(y);
    for (int x = box.x; x < box.br().x; ++x) {
      const int d = sign * (static_cast<int>(a[x]) - static_cast<int>(b[x]));
      if (d < th) continue;
      m.n += 1.0;
      m.sx += x;
      m.sy += y;
      m.sxx += static_cast<double>(x) * x;
      m.syy += static_cast<double>(y) * y;
      m.sxy += static_cast<double>(x) * y;
      m.w += d;
      m.wx += static_cast<double>(d) * x;
      m.wy += static_cast<double>(d) * y;
    }
  }
  return m;
}

// Re-measures a part in a box around itself, twice, so stray noise pixels
// elsewhere in the window do not pull it.
Moments refine(const cv::Mat& cur, const cv::Mat& old, const cv::Rect& roi, int sign, int th,
               Moments m, double margin_px) {
  for (int i = 0; i < 2 && m.w > 0.0; ++i) {
    const Eigen::Vector2d c = m.weighted();
    const double half = 2.0 * std::sqrt(m.n / kPi) + margin_px;
    const cv::Rect box(
        static_cast<int>(std::floor(c.x() - half)), static_cast<int>(std::floor(c.y() - half)),
        static_cast<int>(std::ceil(2.0 * half)) + 1, static_cast<int>(std::ceil(2.0 * half)) + 1);
    m = part_moments(cur, old, box & roi, sign, th);
  }
  return m;
}

// Binary moments of the largest 8-connected part of sign * (cur - old) >=
// th inside `box`: the ball's disc without the noise pixels scattered over
// the box (at 2 grey levels about 1 % of the box; they pulled the centre
// towards the box's middle, i.e. towards the previous estimate).
Moments disc_moments(const cv::Mat& cur, const cv::Mat& old, const cv::Rect& box, int sign,
                     int th) {
  cv::Mat mask(box.size(), CV_8U);
  for (int y = 0; y < box.height; ++y) {
    const uint8_t* a = cur.ptr<uint8_t>(box.y + y) + box.x;
    const uint8_t* b = old.ptr<uint8_t>(box.y + y) + box.x;
    uint8_t* o = mask.ptr<uint8_t>(y);
    for (int x = 0; x < box.width; ++x)
      o[x] = sign * (static_cast<int>(a[x]) - static_cast<int>(b[x])) >= th ? 255 : 0;
  }
  cv::Mat labels, stats, centroids;
  const int count = cv::connectedComponentsWithStats(mask, labels, stats, centroids, 8, CV_32S);
  Moments m;
  int best = 0;
  for (int k = 1; k < count; ++k)
    if (best == 0 || stats.at<int>(k, cv::CC_STAT_AREA) > stats.at<int>(best, cv::CC_STAT_AREA))
      best = k;
  if (best == 0) return m;
  m.n = stats.at<int>(best, cv::CC_STAT_AREA);
  m.sx = (centroids.at<double>(best, 0) + box.x) * m.n;
  m.sy = (centroids.at<double>(best, 1) + box.y) * m.n;
  return m;
}

}  // namespace

double displacement_from_crescent_separation(double separation_px, double r) {
  // The crescent of disc A minus disc B (centres d apart) has its centroid
  // at (pi r^2 / (pi r^2 - lens)) d / 2 from the midpoint; the two crescents
  // are symmetric, so their separation is f(d) = d pi r^2 / (pi r^2 - lens),
  // increasing from pi r / 2 at d -> 0 to d itself once d >= 2 r.
  if (!(r > 0.0)) return separation_px;
  if (separation_px >= 2.0 * r) return separation_px;
  const double disc = kPi * r * r;
  auto f = [&](double d) { return d * disc / (disc - lens_area(d, r)); };
  double lo = 0.0, hi = 2.0 * r;
  if (separation_px <= f(1e-9 * r)) return 0.0;
  for (int i = 0; i < 50; ++i) {
    const double mid = 0.5 * (lo + hi);
    (f(mid) < separation_px ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

MotionCentroid::MotionCentroid(MotionCentroidOptions options) : options_(options) {
  if (options_.frame_gap < 1) throw std::invalid_argument("MotionCentroid: frame_gap must be >= 1");
  reset();
}

void MotionCentroid::reset() {
  ring_.assign(static_cast<size_t>(options_.frame_gap + 1), Frame{});
  frames_ = 0;
  sign_votes_ = 0;
  last_midpoint_.reset();
  learnt_radius_px_ = 0.0;
}

void MotionCentroid::smooth(Frame& f, const cv::Rect& roi) const {
  if ((f.smoothed_rect & roi) == roi) return;  // already smoothed there
  if (f.smoothed.size() != f.raw.size()) f.smoothed.create(f.raw.size(), CV_8U);
  // A ROI of the whole frame: the filter reads real pixels across the ROI's
  // border, so windowed and full-frame results agree.
  cv::Mat dst = f.smoothed(roi);
  cv::GaussianBlur(f.raw(roi), dst, cv::Size(0, 0), options_.smoothing_sigma_px);
  f.smoothed_rect = roi;
}

MotionMeasurement MotionCentroid::process(const cv::Mat& frame,
                                          const std::optional<cv::Rect>& window) {
  const auto t0 = Clock::now();
  MotionMeasurement out = difference(frame, window);
  const bool moved = out.found;  // the difference saw motion
  const Eigen::Vector2d moved_at = out.centroid_px;
  const double moved_area = out.area_px;
  if (options_.background_centre) {
    const size_t slots = ring_.size();
    Frame& cur = ring_[static_cast<size_t>(frames_ + static_cast<long>(slots) - 1) % slots];
    const cv::Rect roi = clip_window(window, frame.size());
    if (has_background_ && roi.area() > 0 && frames_ >= static_cast<long>(slots)) {
      // Near the difference's estimate; the guard when the difference shows
      // nothing (a ball just released, too slow to show).
      std::optional<Eigen::Vector2d> seed;
      if (out.found)
        seed = out.centroid_px;
      else if (guard_centre_)
        seed = guard_centre_;
      // Without the contrast sign the ball's disc and the reference's ghost
      // of it (opposite sign) cannot be told apart: the difference's only.
      if (out.contrast_sign == 0) seed.reset();
      // No disc there against the reference: what the difference saw was
      // not the ball's whole disc (the ball leaving behind the cup, the arm
      // moving); no measurement is better than a wrong one.
      if (seed && seed->allFinite() && !centre_on_background(cur, roi, *seed, out)) {
        out.found = false;
        out.ball_centre = false;
      }
    }
    // A ball-sized motion is guarded even when no disc confirmed it: a ball
    // just released and not yet confirmed (the contrast sign not yet right)
    // must not enter the reference, or its ghost stays at the release point
    // and a wrong sign takes it for the ball. (Not the arm's large motion:
    // a guard on it kept stale pieces of the arm in the reference.)
    MotionMeasurement guarded = out;
    if (!guarded.found && moved && moved_area <= options_.max_vote_area_px) {
      guarded.found = true;
      guarded.centroid_px = moved_at;
    }
    update_background(frame, guarded, moved);
  }
  out.elapsed_ms = ms_since(t0);
  return out;
}

double MotionCentroid::guard_half_px() const {
  const double r = options_.ball_radius_px > 0.0 ? options_.ball_radius_px : learnt_radius_px_;
  // The disc, its blur, and a few px of motion in one frame of a slow ball.
  return std::max(r, 10.0) + 3.0 * options_.smoothing_sigma_px + 4.0;
}

bool MotionCentroid::centre_on_background(Frame& cur, const cv::Rect& roi,
                                          const Eigen::Vector2d& seed, MotionMeasurement& out) {
  const cv::Rect image(0, 0, cur.raw.cols, cur.raw.rows);
  Eigen::Vector2d centre = seed;
  const int th = std::max(1, static_cast<int>(std::ceil(options_.background_threshold)));
  const int sign = out.contrast_sign;
  Moments m;
  for (int pass = 0; pass < 3; ++pass) {
    // The search box: the guard's size around the newest estimate.
    const double half = guard_half_px();
    const cv::Rect box = cv::Rect(static_cast<int>(std::floor(centre.x() - half)),
                                  static_cast<int>(std::floor(centre.y() - half)),
                                  static_cast<int>(std::ceil(2.0 * half)) + 1,
                                  static_cast<int>(std::ceil(2.0 * half)) + 1) &
                         roi & image;
    if (box.area() == 0) return false;
    smooth(cur, box);
    smooth(background_, box);
    m = disc_moments(cur.smoothed, background_.smoothed, box, sign, th);
    if (m.n < options_.min_area_px) return false;
    const Eigen::Vector2d next(m.sx / m.n, m.sy / m.n);
    const bool settled = (next - centre).norm() < 0.05;
    centre = next;
    if (settled) break;
  }
  // More than a disc's area (of the largest radius the guard allows) is not
  // the ball alone: the arm or a shadow moved there; keep the difference's.
  const double half = guard_half_px();
  if (m.n > kPi * half * half) return false;
  // Much less than the disc's recent area: the ball is partly hidden (behind
  // the arm or the cup) and any centroid of it is pulled towards the visible
  // part; none is better (the world model coasts). The area changes slowly
  // along the path (perspective), so a running mean follows it.
  // The recent area is this ball's only while the discs follow each other:
  // a disc far from the last one, or after a few frames without one, is
  // another ball (or this one at another range) and starts a new mean.
  const Eigen::Vector2d here(m.sx / m.n, m.sy / m.n);
  if (frames_ - disc_frame_ > 3 || (here - disc_centre_).norm() > 2.0 * half) disc_area_px_ = 0.0;
  if (disc_area_px_ > 0.0 && m.n < options_.hidden_area_fraction * disc_area_px_) {
    out.found = false;
    out.ball_centre = false;
    out.hidden = true;
    return false;
  }
  disc_area_px_ = disc_area_px_ > 0.0 ? 0.7 * disc_area_px_ + 0.3 * m.n : m.n;
  disc_centre_ = here;
  disc_frame_ = frames_;
  out.found = true;
  out.ball_centre = true;
  out.from_background = true;
  out.centroid_px = centre;
  return true;
}

void MotionCentroid::update_background(const cv::Mat& frame, const MotionMeasurement& out,
                                       bool moved) {
  // The guard follows the ball's centre, but only motion renews its life: a
  // disc against the reference alone could be something the reference kept
  // (the guard would then keep it for ever).
  if (out.found && out.centroid_px.allFinite()) {
    // The box grows by the ball's image motion in one frame: a guard that
    // lags the ball lets its leading edge into the reference, the next
    // centre lags more, and the track falls behind (seen at 5-13 px).
    guard_motion_px_ =
        guard_centre_ && guard_age_ <= 1 ? (out.centroid_px - *guard_centre_).norm() : 0.0;
    guard_centre_ = out.centroid_px;
  }
  if (moved && guard_centre_) {
    guard_age_ = 0;
  } else if (guard_centre_ && ++guard_age_ > options_.guard_frames) {
    guard_centre_.reset();
  }
  if (!has_background_ || !guard_centre_) {
    frame.copyTo(background_.raw);
    has_background_ = true;
  } else {
    // Everything but the guard box: the board as last seen without the ball.
    const double half = guard_half_px() + 2.0 + 1.5 * guard_motion_px_;
    const cv::Rect box = cv::Rect(static_cast<int>(std::floor(guard_centre_->x() - half)),
                                  static_cast<int>(std::floor(guard_centre_->y() - half)),
                                  static_cast<int>(std::ceil(2.0 * half)) + 1,
                                  static_cast<int>(std::ceil(2.0 * half)) + 1) &
                         cv::Rect(0, 0, frame.cols, frame.rows);
    const cv::Mat kept = background_.raw(box).clone();
    frame.copyTo(background_.raw);
    kept.copyTo(background_.raw(box));
  }
  background_.smoothed_rect = cv::Rect();
}

MotionMeasurement MotionCentroid::difference(const cv::Mat& frame,
                                             const std::optional<cv::Rect>& window) {
  const auto t0 = Clock::now();
  const size_t slots = ring_.size();
  Frame& cur = ring_[static_cast<size_t>(frames_) % slots];
  check(frame, ring_[static_cast<size_t>(frames_ + static_cast<long>(slots) - 1) % slots].raw);
  frame.copyTo(cur.raw);
  cur.smoothed_rect = cv::Rect();
  ++frames_;
  MotionMeasurement out;
  out.contrast_sign = options_.contrast_sign != 0 ? options_.contrast_sign : learnt_sign();
  if (frames_ < static_cast<long>(slots)) {
    out.elapsed_ms = ms_since(t0);
    return out;
  }
  Frame& old = ring_[static_cast<size_t>(frames_) % slots];  // frame n - gap
  const cv::Rect roi = clip_window(window, frame.size());
  if (roi.area() == 0) {
    out.elapsed_ms = ms_since(t0);
    return out;
  }
  smooth(cur, roi);
  smooth(old, roi);

  // One pass: the paper's binary moments of |d| > threshold, and weighted
  // moments of the positive and negative parts separately.
  Moments pos, neg;
  const int th = static_cast<int>(std::ceil(options_.threshold));
  for (int y = roi.y; y < roi.br().y; ++y) {
    const uint8_t* a = cur.smoothed.ptr<uint8_t>(y);
    const uint8_t* b = old.smoothed.ptr<uint8_t>(y);
    double row_pn = 0.0, row_psx = 0.0, row_pw = 0.0, row_pwx = 0.0;
    double row_nn = 0.0, row_nsx = 0.0, row_nw = 0.0, row_nwx = 0.0;
    for (int x = roi.x; x < roi.br().x; ++x) {
      const int d = static_cast<int>(a[x]) - static_cast<int>(b[x]);
      if (d >= th) {
        row_pn += 1.0;
        row_psx += x;
        row_pw += d;
        row_pwx += static_cast<double>(d) * x;
      } else if (d <= -th) {
        row_nn += 1.0;
        row_nsx += x;
        row_nw -= d;
        row_nwx -= static_cast<double>(d) * x;
      }
    }
    pos.n += row_pn;
    pos.sx += row_psx;
    pos.sy += row_pn * y;
    pos.w += row_pw;
    pos.wx += row_pwx;
    pos.wy += row_pw * y;
    neg.n += row_nn;
    neg.sx += row_nsx;
    neg.sy += row_nn * y;
    neg.w += row_nw;
    neg.wx += row_nwx;
    neg.wy += row_nw * y;
  }
  out.area_px = pos.n + neg.n;
  const double margin = 2.0 + 2.0 * options_.smoothing_sigma_px;
  if (pos.n > 0.0) pos = refine(cur.smoothed, old.smoothed, roi, 1, th, pos, margin);
  if (neg.n > 0.0) neg = refine(cur.smoothed, old.smoothed, roi, -1, th, neg, margin);
  if (out.area_px < options_.min_area_px || pos.n + neg.n < options_.min_area_px) {
    last_midpoint_.reset();
    out.elapsed_ms = ms_since(t0);
    return out;
  }
  out.found = true;
  // The paper's centroid (eqs 1-3, binary) of the difference blob: both
  // parts, stray pixels elsewhere left out.
  out.plain_centroid_px = {(pos.sx + neg.sx) / (pos.n + neg.n),
                           (pos.sy + neg.sy) / (pos.n + neg.n)};
  out.centroid_px = out.plain_centroid_px;

  const double min_part = std::max(1.0, options_.min_area_px / 4.0);
  if (pos.n < min_part || neg.n < min_part) {
    // Only one part: the ball appeared or left (or only its old or new
    // place is inside the window). Take it if the sign says it is "now".
    last_midpoint_.reset();
    const int sign = out.contrast_sign;
    if (sign > 0 && pos.n >= min_part) {
      out.centroid_px = pos.weighted();
      out.ball_centre = true;
    } else if (sign < 0 && neg.n >= min_part) {
      out.centroid_px = neg.weighted();
      out.ball_centre = true;
    }
    out.elapsed_ms = ms_since(t0);
    return out;
  }
  const Eigen::Vector2d c_pos = pos.weighted(), c_neg = neg.weighted();
  const Eigen::Vector2d mid = 0.5 * (c_pos + c_neg);
  // Learn the contrast sign: the part where the ball is now lies ahead of
  // the midpoint along the motion of the midpoints.
  // Only a ball-sized difference votes: a sign learnt from something else
  // that moved (the arm coming from its park pose before the first ball)
  // made the reference centre the ball on its own ghost at the release
  // point (seed 3).
  if (options_.contrast_sign == 0 && last_midpoint_ && pos.n + neg.n <= options_.max_vote_area_px) {
    const Eigen::Vector2d motion = mid - *last_midpoint_;
    const Eigen::Vector2d pos_ahead = c_pos - c_neg;
    if (motion.norm() > 0.3 && pos_ahead.norm() > 1.0) {
      const double cosine = motion.dot(pos_ahead) / (motion.norm() * pos_ahead.norm());
      if (cosine > 0.5) sign_votes_ = std::min(sign_votes_ + 1, 100);
      if (cosine < -0.5) sign_votes_ = std::max(sign_votes_ - 1, -100);
    }
  }
  last_midpoint_ = mid;
  const int sign = options_.contrast_sign != 0 ? options_.contrast_sign : learnt_sign();
  out.contrast_sign = sign;
  if (sign == 0) {
    out.elapsed_ms = ms_since(t0);
    return out;
  }
  const Moments& now = sign > 0 ? pos : neg;
  const Eigen::Vector2d c_now = sign > 0 ? c_pos : c_neg, c_old = sign > 0 ? c_neg : c_pos;
  const double separation = (c_now - c_old).norm();
  // The two positions are apart when the crescents are farther apart than a
  // disc of the "now" part's area is wide: then the "now" part is the disc.
  const double now_radius = std::sqrt(now.n / kPi);
  const bool apart =
      separation > 2.0 * now_radius + 2.0 * options_.smoothing_sigma_px && now.axis_ratio() > 0.75;
  if (apart) {
    learnt_radius_px_ =
        learnt_radius_px_ > 0.0 ? 0.8 * learnt_radius_px_ + 0.2 * now_radius : now_radius;
  }
  const double radius = options_.ball_radius_px > 0.0 ? options_.ball_radius_px : learnt_radius_px_;
  out.ball_centre = true;
  if (apart || !options_.correct_crescent || !(radius > 0.0) || separation < 1e-9) {
    out.centroid_px = c_now;
  } else {
    const double d = displacement_from_crescent_separation(separation, radius);
    out.centroid_px = mid + (c_now - c_old) * (0.5 * d / separation);
  }
  out.elapsed_ms = ms_since(t0);
  return out;
}

struct Mog2Centroid::Impl {
  cv::Ptr<cv::BackgroundSubtractorMOG2> mog;
  cv::Mat smoothed, mask;
};

Mog2Centroid::Mog2Centroid(Mog2CentroidOptions options)
    : options_(options), impl_(std::make_unique<Impl>()) {
  reset();
}

Mog2Centroid::~Mog2Centroid() = default;

void Mog2Centroid::reset() {
  impl_->mog = cv::createBackgroundSubtractorMOG2(options_.history, options_.var_threshold, false);
}

MotionMeasurement Mog2Centroid::process(const cv::Mat& frame,
                                        const std::optional<cv::Rect>& window) {
  const auto t0 = Clock::now();
  check(frame, impl_->smoothed);
  cv::GaussianBlur(frame, impl_->smoothed, cv::Size(0, 0), options_.smoothing_sigma_px);
  impl_->mog->apply(impl_->smoothed, impl_->mask);
  MotionMeasurement out;
  const cv::Rect roi = clip_window(window, frame.size());
  const cv::Moments m = cv::moments(impl_->mask(roi), true);
  out.area_px = m.m00;
  if (m.m00 >= options_.min_area_px) {
    out.found = true;
    out.centroid_px = {roi.x + m.m10 / m.m00, roi.y + m.m01 / m.m00};
    out.plain_centroid_px = out.centroid_px;
    out.ball_centre = true;
  }
  out.elapsed_ms = ms_since(t0);
  return out;
}

}  // namespace ephor::catching
