#include "procs/shepherd/vision/frame_check.h"

#include <cstdint>

#include "common/shepherd/vision/vision_pipeline.h"

namespace ephor::vision {

std::string check_frame(const camera_frame_t& f) {
  if (f.width <= 0 || f.height <= 0 || f.width > kMaxImageDim || f.height > kMaxImageDim) {
    return "frame " + std::to_string(f.frame_index) + " has size " + std::to_string(f.width) +
           " x " + std::to_string(f.height) + " px (want 1.." + std::to_string(kMaxImageDim) + ")";
  }
  const int64_t want = static_cast<int64_t>(f.width) * f.height;
  if (f.size != want || static_cast<int64_t>(f.data.size()) != want) {
    return "frame " + std::to_string(f.frame_index) + " carries " + std::to_string(f.data.size()) +
           " bytes (size field " + std::to_string(f.size) +
           "), want width * height = " + std::to_string(want);
  }
  return "";
}

}  // namespace ephor::vision
