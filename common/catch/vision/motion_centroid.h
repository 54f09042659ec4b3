#pragma once
// Where the moving ball is, by frame differencing (paper 000, sections 4,
// 5.2-5.3): Gaussian smoothing, the difference of two frames 1/30 s apart
// (at 60 Hz frame n and frame n-2: the same field parity), a threshold, and
// the centroid of the thresholded pixels from the zeroth and first moments
// (eqs 1-3). The ball differs from the board by a few grey levels only, so
// smoothing first is what makes the threshold work.
//
// Beyond the paper:
// - a window of interest around a predicted position (the caller's), the
//   whole image when none;
// - the ball's own centre rather than the difference blob's: the paper's
//   centroid sits between the ball's positions at n-2 and n (it lags by half
//   the displacement). The signed difference separates where the ball is now
//   (sign = the ball's contrast) from where it was; the contrast sign is
//   learnt from the data (the "now" blob lies ahead along the motion of the
//   midpoints) unless given. When the two positions overlap, the "now" part
//   is a crescent whose centroid is ahead of the ball's centre; knowing the
//   ball's image radius (given, or learnt from frames where the two
//   positions are apart) the displacement is solved from the crescents'
//   separation and the centre placed half of it ahead of their midpoint.
// - the ball's whole disc against a reference image of the board without
//   the ball (background_centre, on by default): the crescents above are
//   all frame differencing shows of a ball that moved less than its
//   diameter in 1/30 s, and nothing at all of a ball just released (still);
//   their centre is 1.6 px off at the median and 14 px at the 99th
//   percentile (ephor-catch-harness, seed 1). The reference is the newest
//   frame everywhere except a guard box around the ball's newest centre,
//   where it keeps the board as last seen without the ball; near the
//   difference's estimate (or the guard while the ball is too slow to
//   show in the difference) the pixels of the ball's sign above
//   background_threshold give the centre by their moments (eqs 1-3, binary).
//   Motion still finds the ball; the reference only centres it.
//
// MotionCentroid and the peer Mog2Centroid (OpenCV's MOG2 background
// subtractor) share the MotionDetector interface. Not thread-safe: one
// caller feeds frames in order.

#include <memory>
#include <optional>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

namespace ephor::catching {

struct MotionMeasurement {
  bool found = false;
  // Best estimate of the ball's centre (px): the crescent-corrected centre
  // when ball_centre is true, else the plain centroid.
  Eigen::Vector2d centroid_px = Eigen::Vector2d::Zero();
  // Paper eqs 1-3: centroid of the pixels of |difference| above threshold
  // in the difference blob (both parts; stray pixels elsewhere left out).
  Eigen::Vector2d plain_centroid_px = Eigen::Vector2d::Zero();
  double area_px = 0.0;          // pixels above threshold (zeroth moment)
  bool ball_centre = false;      // centroid_px is the ball's own centre
  bool from_background = false;  // centroid_px is the disc against the reference image
  bool hidden = false;           // the disc was partly hidden: not found
  int contrast_sign = 0;         // +1 ball brighter than the board, -1 darker, 0 not known yet
  double elapsed_ms = 0.0;       // time spent in process()
};

class MotionDetector {
 public:
  virtual ~MotionDetector() = default;
  // Feeds the next frame (8-bit grey, constant size). `window`: where to
  // look (clipped to the image); none = the whole image. Throws
  // std::invalid_argument on a frame of another type or size.
  virtual MotionMeasurement process(const cv::Mat& frame,
                                    const std::optional<cv::Rect>& window = std::nullopt) = 0;
  virtual void reset() = 0;
};

struct MotionCentroidOptions {
  double smoothing_sigma_px = 1.5;  // Gaussian smoothing before differencing
  int frame_gap = 2;                // frames between the two differenced ones
  double threshold = 3.0;           // grey levels of the smoothed difference
  int min_area_px = 30;             // fewer pixels above threshold: not found
  int contrast_sign = 0;            // +1 / -1 if known; 0: learn it from the motion
  int votes_to_learn_sign = 3;      // consistent frames before the learnt sign is trusted
  // A difference larger than this (px, both parts) is not the ball (the arm
  // moving in view) and does not vote on the sign. The ball's is 30-600 px.
  double max_vote_area_px = 1500.0;
  double ball_radius_px = 0.0;        // the ball's image radius if known; 0: learn it
  bool correct_crescent = true;       // false: the "now" blob's own centroid
  bool background_centre = true;      // centre on the disc against the reference (above)
  double background_threshold = 2.0;  // grey levels of the smoothed difference to the reference
  int guard_frames = 30;              // the guard stays this many frames after the last centre
  // A disc against the reference smaller than this fraction of its recent
  // area is a ball partly hidden: reported as not found (hidden).
  double hidden_area_fraction = 0.6;
};

class MotionCentroid : public MotionDetector {
 public:
  explicit MotionCentroid(MotionCentroidOptions options = {});
  MotionMeasurement process(const cv::Mat& frame,
                            const std::optional<cv::Rect>& window = std::nullopt) override;
  void reset() override;

  // The ball radius (px) learnt so far (0 if none) and the learnt sign.
  double learnt_radius_px() const { return learnt_radius_px_; }
  int learnt_sign() const {
    return sign_votes_ >= options_.votes_to_learn_sign    ? 1
           : sign_votes_ <= -options_.votes_to_learn_sign ? -1
                                                          : 0;
  }

 private:
  struct Frame {
    cv::Mat raw;
    cv::Mat smoothed;
    cv::Rect smoothed_rect;  // where `smoothed` is valid
  };
  void smooth(Frame& f, const cv::Rect& roi) const;
  MotionMeasurement difference(const cv::Mat& frame, const std::optional<cv::Rect>& window);
  // The disc against the reference near `seed` (px): found or not.
  bool centre_on_background(Frame& cur, const cv::Rect& roi, const Eigen::Vector2d& seed,
                            MotionMeasurement& out);
  void update_background(const cv::Mat& frame, const MotionMeasurement& out, bool moved);
  double guard_half_px() const;

  MotionCentroidOptions options_;
  std::vector<Frame> ring_;  // frame_gap + 1 slots
  long frames_ = 0;
  int sign_votes_ = 0;
  std::optional<Eigen::Vector2d> last_midpoint_;
  double learnt_radius_px_ = 0.0;
  // The reference image of the board (raw frame; smoothed per window) and
  // the guard: the ball's newest centre (px) and how many frames ago.
  // reset() keeps both: the board does not change when frames are skipped.
  Frame background_;
  bool has_background_ = false;
  std::optional<Eigen::Vector2d> guard_centre_;
  int guard_age_ = 0;
  double guard_motion_px_ = 0.0;  // the centre's motion over the last frame, px
  double disc_area_px_ = 0.0;     // running mean of the disc's area against the reference
  Eigen::Vector2d disc_centre_ = Eigen::Vector2d::Zero();  // the last disc's centre, px
  long disc_frame_ = -100;                                 // and its frame (frames_)
};

// Displacement (px) between two positions of a disc of radius r (px) whose
// symmetric-difference crescents have area centroids `separation` px apart.
// Exposed for tests.
double displacement_from_crescent_separation(double separation_px, double radius_px);

struct Mog2CentroidOptions {
  double smoothing_sigma_px = 1.5;  // the same smoothing as MotionCentroid
  int history = 120;
  double var_threshold = 4.0;  // squared Mahalanobis distance (MOG2's varThreshold)
  int min_area_px = 12;
};

// Peer for the benchmark: cv::BackgroundSubtractorMOG2 on the smoothed
// frame; the centroid of its foreground mask inside the window. MOG2 models
// the background, so its foreground is where the ball is now (no lag), but
// it must see the whole frame every time.
class Mog2Centroid : public MotionDetector {
 public:
  explicit Mog2Centroid(Mog2CentroidOptions options = {});
  ~Mog2Centroid() override;
  MotionMeasurement process(const cv::Mat& frame,
                            const std::optional<cv::Rect>& window = std::nullopt) override;
  void reset() override;

 private:
  struct Impl;
  Mog2CentroidOptions options_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace ephor::catching
