#pragma once
// ImageView and Blob: the plain structs the vision library takes and returns.
//
// Image frame (as camera_frame_t): pixels, origin at the centre of the
// top-left pixel, u to the right (columns), v down (rows). A pixel (u, v)
// covers [u - 0.5, u + 0.5] x [v - 0.5, v + 0.5].

#include <cstdint>
#include <string>

namespace ephor::vision {

// A non-owning view of an 8-bit monochrome image, row-major, row 0 at the top.
// The caller keeps `data` alive while the view is used.
struct ImageView {
  const uint8_t* data = nullptr;
  int width = 0;   // px
  int height = 0;  // px
  int stride = 0;  // bytes from one row to the next (>= width)

  uint8_t at(int u, int v) const { return data[static_cast<std::ptrdiff_t>(v) * stride + u]; }
};

// Largest width or height the vision library accepts: pixel coordinates are
// packed into 16 bits in the fill stack, and it bounds the buffers a single
// consistent-but-absurd frame can make the Blobifier allocate (~100 MB).
inline constexpr int kMaxImageDim = 4096;

// "" when `image` can be searched, else a message naming the problem
// (null data, non-positive or too large dimensions, stride < width).
std::string check_image(const ImageView& image);

// How a blob is measured once a sample hits it.
enum class ScanMode : int8_t {
  kFull = 0,  // explicit-stack 4-neighbour fill of every pixel (exact)
  kAxis = 1,  // the paper's quick-circle axis scan (fast; assumes a round blob)
};

// One connected region of pixels brighter than the threshold.
struct Blob {
  float u = 0.0f;     // centroid column, px (mean of the member pixels' u)
  float v = 0.0f;     // centroid row, px
  int32_t area = 0;   // member pixels (estimated from the two diameters in axis scan)
  int32_t u_min = 0;  // bounding box, inclusive, px
  int32_t v_min = 0;
  int32_t u_max = 0;
  int32_t v_max = 0;
};

}  // namespace ephor::vision
