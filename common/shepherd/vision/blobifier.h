#pragma once
// Blobifier: the two-phase sparse blob search of the shepherding paper
// (section 4.1, "Blobify").
//
// Phase one samples every k-th pixel of every k-th row (the sparse "shadow"
// grid). Phases are combined as in the paper: the moment a sample is above
// the threshold, phase one pauses and the blob under it is measured at full
// resolution, either
//  - ScanMode::kFull: an iterative fill with an explicit stack of pixels
//    (4-neighbour), accumulating area, sum u, sum v and the bounding box; or
//  - ScanMode::kAxis: the paper's quick-circle scan: a vertical run through
//    the hit, a horizontal run through its middle, a second vertical run
//    through the middle of that; the centre is where the diameters cross,
//    refined to sub-pixel by interpolating the threshold crossing at each end.
//    When the blob is not round enough (the two vertical midpoints disagree,
//    e.g. a mark half hidden by the arm) it falls back to the full fill.
// Every pixel a fill expands is marked, so a later sample landing on the same
// blob is skipped and no blob is found twice (the paper marks the shadow cells
// "do not expand"; here the marks are per pixel, so the same array serves the
// sparse grid and the fill). An axis scan marks the samples inside the blob's
// bounding box instead.
//
// Buffers (marks, stack, blob list) are kept between frames: in steady state
// a frame allocates nothing. Marks are frame-stamped, so starting a frame costs
// O(1), not a clear of the whole image.
//
// A blob is found only when at least one sample lands on it: a blob that
// contains a k x k square of above-threshold pixels is always found; a
// smaller one may fall between samples and be missed (choose k below the
// smallest mark diameter).
//
// Not thread-safe: one Blobifier per thread.

#include <cstdint>
#include <vector>

#include "common/shepherd/vision/image_view.h"

namespace ephor::vision {

struct BlobifierConfig {
  int sample_step = 4;  // k: sample every k-th pixel of every k-th row, px (>= 1)
  int min_area = 10;    // blobs with fewer pixels are noise and dropped, px
  int max_blobs = 256;  // stop searching after this many blobs (bounds the time per frame)
  // Axis scan: largest distance between the midpoints of the two vertical
  // runs for the blob to count as round, px; rounder blobs keep the axis
  // estimate, others are filled.
  float axis_roundness_px = 1.5f;
};

// Counters of the last frame (reset by begin_frame).
struct BlobifierStats {
  int64_t samples = 0;         // sparse-grid samples examined
  int64_t pixels_filled = 0;   // pixels accumulated by fills
  int32_t noise_blobs = 0;     // regions dropped for area < min_area
  int32_t axis_fallbacks = 0;  // axis scans that fell back to a fill
  bool truncated = false;      // max_blobs reached: the search stopped there (more may exist)
};

class Blobifier {
 public:
  // Throws std::invalid_argument naming the field when `config` is out of range.
  explicit Blobifier(BlobifierConfig config = {});

  // Finds every blob of pixels > threshold that a sample of the k-grid hits.
  // The returned list stays valid until the next call on this object.
  // Throws std::invalid_argument when check_image(image) fails.
  const std::vector<Blob>& blobify(const ImageView& image, uint8_t threshold, ScanMode scan);

  // Building blocks (used by Trackifier). begin_frame() forgets the previous
  // frame's blobs and marks; `image` must stay alive until the next one.
  void begin_frame(const ImageView& image, uint8_t threshold, ScanMode scan);
  // Measures the blob containing (u, v) if that pixel is in the image, above
  // the threshold and not yet part of a blob of this frame. Returns true when
  // a blob (area >= min_area) was added.
  bool expand_at(int u, int v);
  // Phase one over the sample-grid points inside [u0, u1) x [v0, v1) (the grid
  // is anchored at pixel (0, 0), so bands and full scans share samples).
  void sparse_scan(int u0, int v0, int u1, int v1);
  // Starts fetching the pixels of [u0, u1] x [v0, v1] (inclusive, clipped)
  // into the cache, so that several blobs' rows arrive from memory together.
  void prefetch_box(int u0, int v0, int u1, int v1) const;
  // True when (u, v) is above the threshold and not yet part of a blob.
  bool is_free_object_pixel(int u, int v) const;

  const std::vector<Blob>& blobs() const { return blobs_; }
  const BlobifierStats& stats() const { return stats_; }
  const BlobifierConfig& config() const { return config_; }

 private:
  static void prefetch_span(const uint8_t* p, int n);
  bool full_fill(int u, int v);
  bool axis_scan(int u, int v);
  // Threshold crossing of a run ending at `last` (inside) going in direction
  // d, sub-pixel, px along the run.
  float edge(int u, int v, int du, int dv) const;
  bool marked(int u, int v) const { return marks_[index(u, v)] == stamp_; }
  void mark(int u, int v) { marks_[index(u, v)] = stamp_; }
  size_t index(int u, int v) const {
    return static_cast<size_t>(v) * static_cast<size_t>(width_) + static_cast<size_t>(u);
  }
  bool above(int u, int v) const { return image_.at(u, v) > threshold_; }
  bool add_blob(const Blob& blob);  // false when the list is full

  BlobifierConfig config_;
  ImageView image_;
  int width_ = 0;
  int height_ = 0;
  uint8_t threshold_ = 128;
  ScanMode scan_ = ScanMode::kFull;
  // marks_[v * width + u] == stamp_ when the pixel belongs to a blob of this
  // frame (or, in axis scan, is a sample inside a found blob's box).
  std::vector<uint16_t> marks_;
  uint16_t stamp_ = 0;
  std::vector<uint32_t> stack_;  // pending pixels, (v << 16) | u
  std::vector<Blob> blobs_;
  BlobifierStats stats_;
};

}  // namespace ephor::vision
