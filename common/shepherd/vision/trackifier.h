#pragma once
// Trackifier: the paper's "trackify" (section 4.1): instead of searching the
// whole image, re-measure each blob from where it was in the last frame, then
// search only a band along the image border for new arrivals ("sheep can't
// fly": objects enter the field from its edge).
//
// A blob is re-grown from its previous centroid, or, when that pixel is no
// longer above the threshold (the mark moved or is partly hidden), from the
// nearest free above-threshold pixel within `search_radius_px`. This holds
// while a blob moves less than about its radius per frame (the paper: sheep
// moved 2-3 px/s, marks were 16 px, 20 Hz).
//
// A blob that appears inside the field (a sheep that slid in under the arm, a
// mark that reappears after an occlusion) is invisible to trackify; a full
// blobify every `full_every` frames, or on request, recovers it.
//
// Not thread-safe; uses the caller's Blobifier (its buffers and settings,
// including k for the band scan).

#include <cstdint>
#include <vector>

#include "common/shepherd/vision/blobifier.h"
#include "common/shepherd/vision/image_view.h"

namespace ephor::vision {

struct TrackifierConfig {
  int band_px = 16;          // width of the border band searched for new blobs, px (>= 1)
  int search_radius_px = 4;  // how far from a previous centroid a seed is looked for, px (>= 0)
  int full_every = 15;       // a full blobify every this many frames; 0 = only when needed
};

class Trackifier {
 public:
  // Throws std::invalid_argument naming the field when `config` is out of range.
  explicit Trackifier(TrackifierConfig config = {});

  // Finds this frame's blobs. Runs a full blobify on the first frame, after
  // reset() or request_full(), after a change of image size, and every
  // `full_every` frames; otherwise the track-and-band search. Returns
  // `blobifier.blobs()`. Throws std::invalid_argument for an invalid image.
  const std::vector<Blob>& track(Blobifier& blobifier, const ImageView& image, uint8_t threshold,
                                 ScanMode scan);

  // The next track() searches the whole image.
  void request_full() { full_requested_ = true; }
  // Forgets the previous blobs (the next track() is a full blobify).
  void reset();

  // True when the last track() was a full blobify.
  bool last_was_full() const { return last_was_full_; }
  const TrackifierConfig& config() const { return config_; }

 private:
  // Seed pixel for re-growing the blob last seen at (u, v), or false.
  bool find_seed(const Blobifier& blobifier, float u, float v, int* su, int* sv) const;

  TrackifierConfig config_;
  std::vector<Blob> previous_;  // blobs of the last frame (capacity kept)
  bool has_previous_ = false;
  bool full_requested_ = false;
  bool last_was_full_ = false;
  int frames_since_full_ = 0;
  int width_ = 0;
  int height_ = 0;
};

}  // namespace ephor::vision
