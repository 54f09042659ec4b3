#pragma once
// ThresholdSelector: picks the grey level that separates bright marks from the
// dark field, with the rule of the shepherding paper (section 2.3): take the
// histogram, find the background peak and the object peak, and put the
// threshold between them, 80-90 % of the way toward the object peak (less
// noise around the blob perimeters than the midpoint).
//
// The object peak may be tiny (six 16 px marks are 0.5 % of a 512 x 482
// frame), so it is not found as "the second largest maximum": the background
// lobe is walked down to its tail first, and the object peak is the largest
// (smoothed) bin above that tail, accepted only when it holds enough pixels
// and stands out from the rest of the tail.

#include <array>
#include <cstdint>
#include <string>

#include "common/shepherd/vision/image_view.h"

namespace ephor::vision {

using Histogram = std::array<uint32_t, 256>;  // pixels per grey level

struct ThresholdSelectorConfig {
  // Where the threshold goes between the peaks: 0 = background, 1 = object.
  double fraction = 0.85;
  // Half width of the box filter applied to the histogram, grey levels.
  int smooth_radius = 2;
  // The background lobe ends at the first level above its peak where the
  // smoothed count falls below this fraction of the peak's count (and then
  // continues down to the bottom of the valley).
  double tail_fraction = 1e-3;
  // The object peak must hold at least this many pixels within
  // +-smooth_radius levels (a 5 x 5 px mark has 25).
  int min_object_pixels = 20;
  // ... and its smoothed count must be at least this many times the mean
  // smoothed count above the background tail (rejects flat noise).
  double min_prominence = 3.0;
};

enum class ThresholdStatus {
  kOk,              // both peaks found; `threshold` follows the paper's rule
  kEmptyHistogram,  // no pixels at all
  kNoObjectPeak,    // only a background lobe; `threshold` is provisional
};

struct ThresholdChoice {
  ThresholdStatus status = ThresholdStatus::kEmptyHistogram;
  // Grey level; a pixel is "object" when its value is > threshold. Always in
  // 1..254. When status is kNoObjectPeak it is a provisional value halfway
  // between the background tail and 255, so that marks arriving later are
  // still seen; when kEmptyHistogram it is 128.
  int threshold = 128;
  int background_peak = -1;  // grey level, -1 when not found
  int background_tail = -1;  // first grey level past the background lobe, -1 when none
  int object_peak = -1;      // grey level, -1 when not found
  std::string message;       // why the status is not kOk, else ""
};

class ThresholdSelector {
 public:
  // Throws std::invalid_argument naming the field when `config` is out of range.
  explicit ThresholdSelector(ThresholdSelectorConfig config = {});

  static Histogram histogram(const ImageView& image);

  ThresholdChoice select(const Histogram& histogram) const;
  ThresholdChoice select(const ImageView& image) const { return select(histogram(image)); }

  const ThresholdSelectorConfig& config() const { return config_; }

 private:
  ThresholdSelectorConfig config_;
};

}  // namespace ephor::vision
