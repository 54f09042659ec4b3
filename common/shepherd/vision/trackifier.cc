#include "common/shepherd/vision/trackifier.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace ephor::vision {

Trackifier::Trackifier(TrackifierConfig config) : config_(config) {
  if (config_.band_px < 1) {
    throw std::invalid_argument("trackifier band_px must be >= 1 px, got " +
                                std::to_string(config_.band_px));
  }
  if (config_.search_radius_px < 0 || config_.search_radius_px > 64) {
    throw std::invalid_argument("trackifier search_radius_px must be in 0..64 px, got " +
                                std::to_string(config_.search_radius_px));
  }
  if (config_.full_every < 0) {
    throw std::invalid_argument("trackifier full_every must be >= 0 frames, got " +
                                std::to_string(config_.full_every));
  }
  previous_.reserve(256);
}

void Trackifier::reset() {
  previous_.clear();
  has_previous_ = false;
  frames_since_full_ = 0;
}

bool Trackifier::find_seed(const Blobifier& blobifier, float u, float v, int* su, int* sv) const {
  const int uc = static_cast<int>(std::lround(u));
  const int vc = static_cast<int>(std::lround(v));
  if (blobifier.is_free_object_pixel(uc, vc)) {
    *su = uc;
    *sv = vc;
    return true;
  }
  // Nearest free object pixel in the (2r+1)^2 window, by squared distance
  // from the previous centroid.
  const int r = config_.search_radius_px;
  float best = 1e30f;
  bool found = false;
  for (int dv = -r; dv <= r; ++dv) {
    for (int du = -r; du <= r; ++du) {
      const int pu = uc + du;
      const int pv = vc + dv;
      if (!blobifier.is_free_object_pixel(pu, pv)) continue;
      const float eu = static_cast<float>(pu) - u;
      const float ev = static_cast<float>(pv) - v;
      const float d2 = eu * eu + ev * ev;
      if (d2 < best) {
        best = d2;
        *su = pu;
        *sv = pv;
        found = true;
      }
    }
  }
  return found;
}

const std::vector<Blob>& Trackifier::track(Blobifier& blobifier, const ImageView& image,
                                           uint8_t threshold, ScanMode scan) {
  const bool resized = image.width != width_ || image.height != height_;
  const bool full = !has_previous_ || full_requested_ || resized ||
                    (config_.full_every > 0 && frames_since_full_ + 1 >= config_.full_every);
  const std::vector<Blob>* found = nullptr;
  if (full) {
    found = &blobifier.blobify(image, threshold, scan);
    frames_since_full_ = 0;
    full_requested_ = false;
  } else {
    blobifier.begin_frame(image, threshold, scan);
    // Fetch every old blob's neighbourhood and the side bands' samples at
    // once: when the frame is not in the cache their memory latencies overlap.
    const int m = config_.search_radius_px + 2;
    for (const Blob& b : previous_) {
      blobifier.prefetch_box(b.u_min - m, b.v_min - m, b.u_max + m, b.v_max + m);
    }
    for (const Blob& b : previous_) {
      int su = 0, sv = 0;
      if (find_seed(blobifier, b.u, b.v, &su, &sv)) blobifier.expand_at(su, sv);
    }
    // The border band: top and bottom strips over the full width, then the
    // left and right strips between them.
    const int w = image.width;
    const int h = image.height;
    const int band = config_.band_px;
    if (2 * band >= h || 2 * band >= w) {
      blobifier.sparse_scan(0, 0, w, h);
    } else {
      blobifier.sparse_scan(0, 0, w, band);
      blobifier.sparse_scan(0, h - band, w, h);
      blobifier.sparse_scan(0, band, band, h - band);
      blobifier.sparse_scan(w - band, band, w, h - band);
    }
    found = &blobifier.blobs();
    ++frames_since_full_;
  }
  width_ = image.width;
  height_ = image.height;
  last_was_full_ = full;
  previous_.assign(found->begin(), found->end());
  has_previous_ = true;
  return *found;
}

}  // namespace ephor::vision
