#pragma once
// SyntheticImage: renders test and benchmark frames for the vision library:
// a dark field, bright round marks antialiased by their exact pixel coverage
// (so a sub-pixel centre is visible in the grey levels), rectangles, single
// pixels, and Gaussian pixel noise from a seeded generator. Used by the unit
// tests and ephor-bench-vision; not by the vision process itself.

#include <cstdint>
#include <random>
#include <vector>

#include "common/shepherd/vision/image_view.h"

namespace ephor::vision {

class SyntheticImage {
 public:
  // A width x height px field of grey level `background`.
  SyntheticImage(int width, int height, float background);

  // Sets every pixel to `level`.
  void fill(float level);
  // A disc centred at (cu, cv) px (image frame) of radius `radius` px: each
  // pixel moves toward `level` by the fraction of its area inside the disc
  // (16 x 16 sub-samples on the rim).
  void add_disc(double cu, double cv, double radius, float level);
  // Pixels u0..u1, v0..v1 (inclusive, clipped to the image) set to `level`.
  void add_rect(int u0, int v0, int u1, int v1, float level);
  void set(int u, int v, float level);

  // Quantises to 8 bits after adding zero-mean Gaussian noise of `sigma`
  // grey levels (0 = none), clamped to 0..255. The view stays valid until
  // the next render() or the object's destruction.
  ImageView render(double noise_sigma, std::mt19937& rng);
  ImageView render() {
    std::mt19937 unused(0);
    return render(0.0, unused);
  }

  int width() const { return width_; }
  int height() const { return height_; }
  const std::vector<uint8_t>& pixels() const { return pixels_; }

 private:
  int width_;
  int height_;
  std::vector<float> level_;     // clean grey levels
  std::vector<uint8_t> pixels_;  // last render
};

}  // namespace ephor::vision
