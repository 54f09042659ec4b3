#include "common/shepherd/vision/image_view.h"

namespace ephor::vision {

std::string check_image(const ImageView& image) {
  if (image.data == nullptr) return "image has no pixel data";
  if (image.width <= 0 || image.height <= 0 || image.width > kMaxImageDim ||
      image.height > kMaxImageDim) {
    return "image size " + std::to_string(image.width) + " x " + std::to_string(image.height) +
           " px is outside 1.." + std::to_string(kMaxImageDim);
  }
  if (image.stride < image.width) {
    return "image stride " + std::to_string(image.stride) + " is smaller than its width " +
           std::to_string(image.width);
  }
  return "";
}

}  // namespace ephor::vision
