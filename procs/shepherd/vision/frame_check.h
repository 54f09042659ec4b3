// The check ephor-vision makes of every CAMERA_FRAME before it searches the
// image: the message's fields must agree with each other. A camera (or a
// fuzzer, or a bad log) may send a size field, a pixel count or a width and
// height that disagree; such a frame is refused with the reason, counted and
// logged, never searched.
#pragma once

#include <string>

#include "ephor/camera_frame_t.hpp"

namespace ephor::vision {

// "" when the frame's width and height are within 1..kMaxImageDim px and its
// size field and pixel count both equal width * height (8-bit grey, rows
// packed); otherwise the problem, naming the frame.
std::string check_frame(const camera_frame_t& f);

}  // namespace ephor::vision
