#include "common/shepherd/vision/blobifier.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace ephor::vision {
namespace {

constexpr uint32_t pack(int u, int v) {
  return (static_cast<uint32_t>(v) << 16) | static_cast<uint32_t>(u);
}

// First multiple of k that is >= x (x >= 0).
int first_grid_at_or_after(int x, int k) { return ((x + k - 1) / k) * k; }

}  // namespace

Blobifier::Blobifier(BlobifierConfig config) : config_(config) {
  if (config_.sample_step < 1 || config_.sample_step > 256) {
    throw std::invalid_argument("blobifier sample_step (k) must be in 1..256 px, got " +
                                std::to_string(config_.sample_step));
  }
  if (config_.min_area < 1) {
    throw std::invalid_argument("blobifier min_area must be >= 1 px, got " +
                                std::to_string(config_.min_area));
  }
  if (config_.max_blobs < 1) {
    throw std::invalid_argument("blobifier max_blobs must be >= 1, got " +
                                std::to_string(config_.max_blobs));
  }
  if (!(config_.axis_roundness_px > 0.0f)) {
    throw std::invalid_argument("blobifier axis_roundness_px must be > 0");
  }
  blobs_.reserve(static_cast<size_t>(config_.max_blobs));
}

const std::vector<Blob>& Blobifier::blobify(const ImageView& image, uint8_t threshold,
                                            ScanMode scan) {
  begin_frame(image, threshold, scan);
  sparse_scan(0, 0, width_, height_);
  return blobs_;
}

void Blobifier::begin_frame(const ImageView& image, uint8_t threshold, ScanMode scan) {
  const std::string problem = check_image(image);
  if (!problem.empty()) throw std::invalid_argument(problem);
  image_ = image;
  threshold_ = threshold;
  scan_ = scan;
  if (image.width != width_ || image.height != height_) {
    width_ = image.width;
    height_ = image.height;
    const size_t n = static_cast<size_t>(width_) * static_cast<size_t>(height_);
    marks_.assign(n, 0);
    // Each pixel is pushed at most once (it is marked when pushed).
    stack_.resize(n);
    stamp_ = 0;
  }
  if (++stamp_ == 0) {  // the stamp wrapped: old marks could look current
    std::fill(marks_.begin(), marks_.end(), uint16_t{0});
    stamp_ = 1;
  }
  blobs_.clear();
  stats_ = BlobifierStats{};
}

bool Blobifier::is_free_object_pixel(int u, int v) const {
  if (u < 0 || v < 0 || u >= width_ || v >= height_) return false;
  return above(u, v) && !marked(u, v);
}

bool Blobifier::expand_at(int u, int v) {
  if (stats_.truncated || !is_free_object_pixel(u, v)) return false;
  if (scan_ == ScanMode::kAxis) {
    // An axis scan marks only the samples in a blob's box; a seed that is not
    // a sample (Trackifier's previous centroid) is checked against the boxes.
    for (const Blob& b : blobs_) {
      if (u >= b.u_min && u <= b.u_max && v >= b.v_min && v <= b.v_max) return false;
    }
    return axis_scan(u, v);
  }
  return full_fill(u, v);
}

void Blobifier::prefetch_span(const uint8_t* p, int n) {
  for (int i = 0; i < n; i += 64) __builtin_prefetch(p + i);
  if (n > 0) __builtin_prefetch(p + n - 1);
}

void Blobifier::prefetch_box(int u0, int v0, int u1, int v1) const {
  u0 = std::max(u0, 0);
  v0 = std::max(v0, 0);
  u1 = std::min(u1, width_ - 1);
  v1 = std::min(v1, height_ - 1);
  if (u0 > u1) return;
  for (int v = v0; v <= v1; ++v) {
    prefetch_span(image_.data + static_cast<std::ptrdiff_t>(v) * image_.stride + u0, u1 - u0 + 1);
  }
}

void Blobifier::sparse_scan(int u0, int v0, int u1, int v1) {
  const int k = config_.sample_step;
  u0 = std::max(u0, 0);
  v0 = std::max(v0, 0);
  u1 = std::min(u1, width_);
  v1 = std::min(v1, height_);
  if (u0 >= u1 || v0 >= v1) return;
  const int us = first_grid_at_or_after(u0, k);
  const int vs = first_grid_at_or_after(v0, k);
  if (us >= u1) return;
  const int per_row = (u1 - 1 - us) / k + 1;
  const uint8_t thr = threshold_;
  for (int v = vs; v < v1; v += k) {
    const uint8_t* row = image_.data + static_cast<std::ptrdiff_t>(v) * image_.stride;
    stats_.samples += per_row;
    // Ask for the next sampled row now: rows k apart defeat the hardware
    // prefetcher, and a frame that is not in the cache then costs one DRAM
    // round trip per row instead of overlapping them.
    if (v + k < v1)
      prefetch_span(row + static_cast<std::ptrdiff_t>(k) * image_.stride + us, u1 - us);
    // Whole-row prefilter: on a mostly dark field almost every sampled row is
    // rejected with a few vector max instructions. The row's cache lines are
    // read anyway by a stride-k scan (k < 64), so this costs no extra memory
    // traffic; only grid samples can start a blob, as in the paper.
    uint8_t brightest = 0;
    for (int u = us; u < u1; ++u) brightest = std::max(brightest, row[u]);
    if (brightest <= thr) continue;
    for (int u = us; u < u1; u += k) {
      if (row[u] > thr && !marked(u, v)) {
        if (scan_ == ScanMode::kAxis) {
          axis_scan(u, v);
        } else {
          full_fill(u, v);
        }
        if (stats_.truncated) return;
      }
    }
  }
}

bool Blobifier::full_fill(int u_seed, int v_seed) {
  // Locals so the compiler keeps them in registers across the loop.
  const uint8_t thr = threshold_;
  const uint16_t st = stamp_;
  const int w = width_;
  const int h = height_;
  const std::ptrdiff_t stride = image_.stride;
  const uint8_t* img = image_.data;
  uint16_t* marks = marks_.data();
  uint32_t* stack = stack_.data();
  size_t sp = 0;

  marks[index(u_seed, v_seed)] = st;
  stack[sp++] = pack(u_seed, v_seed);
  int64_t area = 0;
  int64_t sum_u = 0;
  int64_t sum_v = 0;
  int u_min = u_seed, u_max = u_seed, v_min = v_seed, v_max = v_seed;
  while (sp > 0) {
    const uint32_t q = stack[--sp];
    const int u = static_cast<int>(q & 0xffffu);
    const int v = static_cast<int>(q >> 16);
    ++area;
    sum_u += u;
    sum_v += v;
    u_min = std::min(u_min, u);
    u_max = std::max(u_max, u);
    v_min = std::min(v_min, v);
    v_max = std::max(v_max, v);
    const uint8_t* p = img + static_cast<std::ptrdiff_t>(v) * stride + u;
    uint16_t* m = marks + static_cast<std::ptrdiff_t>(v) * w + u;
    if (u > 0 && p[-1] > thr && m[-1] != st) {
      m[-1] = st;
      stack[sp++] = q - 1;
    }
    if (u + 1 < w && p[1] > thr && m[1] != st) {
      m[1] = st;
      stack[sp++] = q + 1;
    }
    if (v > 0 && p[-stride] > thr && m[-w] != st) {
      m[-w] = st;
      stack[sp++] = q - 0x10000u;
    }
    if (v + 1 < h && p[stride] > thr && m[w] != st) {
      m[w] = st;
      stack[sp++] = q + 0x10000u;
    }
  }
  stats_.pixels_filled += area;
  if (area < config_.min_area) {
    ++stats_.noise_blobs;
    return false;
  }
  Blob b;
  b.u = static_cast<float>(static_cast<double>(sum_u) / static_cast<double>(area));
  b.v = static_cast<float>(static_cast<double>(sum_v) / static_cast<double>(area));
  b.area = static_cast<int32_t>(area);
  b.u_min = u_min;
  b.u_max = u_max;
  b.v_min = v_min;
  b.v_max = v_max;
  return add_blob(b);
}

float Blobifier::edge(int u, int v, int du, int dv) const {
  const int un = u + du;
  const int vn = v + dv;
  if (un < 0 || vn < 0 || un >= width_ || vn >= height_) return 0.5f;  // the image border
  const float in = image_.at(u, v);
  const float out = image_.at(un, vn);
  // in > threshold >= out, so the crossing is in (0, 1] pixel past `last`.
  return (in - static_cast<float>(threshold_)) / (in - out);
}

bool Blobifier::axis_scan(int u0, int v0) {
  // 1: vertical run through the hit.
  int top = v0, bot = v0;
  while (top > 0 && above(u0, top - 1)) --top;
  while (bot + 1 < height_ && above(u0, bot + 1)) ++bot;
  const float mid_v1 = 0.5f * ((static_cast<float>(top) - edge(u0, top, 0, -1)) +
                               (static_cast<float>(bot) + edge(u0, bot, 0, 1)));
  const int vr = std::clamp(static_cast<int>(std::lround(mid_v1)), top, bot);
  // 2: horizontal run through its middle: the horizontal diameter.
  int left = u0, right = u0;
  while (left > 0 && above(left - 1, vr)) --left;
  while (right + 1 < width_ && above(right + 1, vr)) ++right;
  const float l = static_cast<float>(left) - edge(left, vr, -1, 0);
  const float r = static_cast<float>(right) + edge(right, vr, 1, 0);
  const float mid_u = 0.5f * (l + r);
  const int ur = std::clamp(static_cast<int>(std::lround(mid_u)), left, right);
  // 3: vertical run through the middle of the diameter: the check.
  int top2 = vr, bot2 = vr;
  while (top2 > 0 && above(ur, top2 - 1)) --top2;
  while (bot2 + 1 < height_ && above(ur, bot2 + 1)) ++bot2;
  const float t2 = static_cast<float>(top2) - edge(ur, top2, 0, -1);
  const float b2 = static_cast<float>(bot2) + edge(ur, bot2, 0, 1);
  const float mid_v2 = 0.5f * (t2 + b2);
  const float diam_u = r - l;
  const float diam_v = b2 - t2;
  const float tol = config_.axis_roundness_px;
  if (std::fabs(mid_v2 - mid_v1) > tol || std::fabs(diam_u - diam_v) > 2.0f * tol) {
    ++stats_.axis_fallbacks;
    return full_fill(u0, v0);
  }
  Blob b;
  b.u = mid_u;
  b.v = mid_v2;
  b.area = static_cast<int32_t>(std::lround(std::numbers::pi_v<float> / 4.0f * diam_u * diam_v));
  b.u_min = left;
  b.u_max = right;
  b.v_min = std::min(top, top2);
  b.v_max = std::max(bot, bot2);
  // Mark the samples inside the box so the sparse scan does not hit the blob
  // again (the paper's "do not expand" shadow cells).
  const int k = config_.sample_step;
  for (int v = first_grid_at_or_after(b.v_min, k); v <= b.v_max; v += k) {
    for (int u = first_grid_at_or_after(b.u_min, k); u <= b.u_max; u += k) mark(u, v);
  }
  mark(u0, v0);
  if (b.area < config_.min_area) {
    ++stats_.noise_blobs;
    return false;
  }
  return add_blob(b);
}

bool Blobifier::add_blob(const Blob& blob) {
  if (static_cast<int>(blobs_.size()) >= config_.max_blobs) {
    stats_.truncated = true;
    return false;
  }
  blobs_.push_back(blob);
  // Full: stop the search here rather than measure blobs that cannot be kept.
  if (static_cast<int>(blobs_.size()) >= config_.max_blobs) stats_.truncated = true;
  return true;
}

}  // namespace ephor::vision
