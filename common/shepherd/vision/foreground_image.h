#pragma once
// ForegroundImage: turns a camera frame into an image in which the objects to
// track are bright on dark, so the Blobifier (pixels > threshold) can find
// them whatever the scene looks like:
//  - kBright: the frame as it is (the shepherding field: white marks on a
//    dark floor); no copy.
//  - kDark: the inverted frame, 255 - pixel (dark objects on a bright floor:
//    the "inverted threshold").
//  - kMotion: NASREM's motion detection (seed 000): |frame - reference|,
//    where the reference is the previous frame (background_rate 1, plain
//    frame differencing) or a running average of past frames (rate < 1:
//    reference += rate * (frame - reference) after each frame), so a
//    moving object lights up and a still background stays dark. Frame
//    differencing lights up only the edges of a uniform object (its leading
//    and trailing borders), so the difference can be box-smoothed over
//    +-smooth_radius_px to join the fragments of one object into one blob.
//    The first frame (and the first after a size change) has no reference:
//    its motion image is black.
//
// Units: grey levels (0..255), px. Not thread-safe: one per vision task.

#include <cstdint>
#include <string>
#include <vector>

#include "common/shepherd/vision/image_view.h"

namespace ephor::vision {

enum class ForegroundMode : int8_t {
  kBright = 0,  // objects brighter than the background
  kDark = 1,    // objects darker than the background
  kMotion = 2,  // objects that move (frame differencing)
};

// "bright" / "dark" / "motion"; parse_foreground_mode throws
// std::invalid_argument naming the text otherwise.
const char* foreground_mode_name(ForegroundMode mode);
ForegroundMode parse_foreground_mode(const std::string& text);

struct ForegroundConfig {
  ForegroundMode mode = ForegroundMode::kBright;
  // kMotion: weight of the newest frame in the reference (0 < rate <= 1;
  // 1 = the previous frame).
  double background_rate = 1.0;
  // kMotion: half width of the box filter over the difference, px (0 = none).
  int smooth_radius_px = 0;
};

class ForegroundImage {
 public:
  // Throws std::invalid_argument naming the field when `config` is out of range.
  explicit ForegroundImage(ForegroundConfig config = {});

  // The foreground of `frame` (see the modes above). The returned view stays
  // valid until the next call (kBright returns `frame` itself). Throws
  // std::invalid_argument when check_image(frame) fails.
  ImageView apply(const ImageView& frame);

  // Forgets the motion reference (the next frame starts it again).
  void reset() { reference_.clear(); }
  const ForegroundConfig& config() const { return config_; }

 private:
  void difference(const ImageView& frame);
  void smooth(int width, int height);

  ForegroundConfig config_;
  int width_ = 0;
  int height_ = 0;
  std::vector<float> reference_;  // motion reference, grey levels, width_ * height_
  std::vector<uint8_t> out_;      // the returned image, width_ * height_
  std::vector<uint32_t> sums_;    // integral image for the box filter, (w + 1) * (h + 1)
};

}  // namespace ephor::vision
