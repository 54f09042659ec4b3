// Fuzz target (issue 18): camera frames as ephor-vision handles them: the
// settings of a VISION_CMD (checked, applied only when valid), then up to
// four CAMERA_FRAMEs, each checked by check_frame() as the process checks
// it (a size field or a pixel count that disagrees with width x height is
// refused) and searched by the VisionPipeline, whose state (threshold,
// tracks) carries from frame to frame. Sizes up to 96 x 96 px with the
// pixels taken from the input, so blobs of any shape, all-object frames and
// noise all come up; the size limits themselves (kMaxImageDim) are checked
// without pixels. Seeds: fuzz_corpus/shepherd_vision.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "common/fuzz/fuzz_input.h"
#include "common/shepherd/vision/vision_pipeline.h"
#include "ephor/camera_frame_t.hpp"
#include "procs/shepherd/vision/frame_check.h"

using ephor::fuzz::FuzzBytes;
namespace vision = ephor::vision;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  FuzzBytes in(data, size);
  vision::VisionPipeline pipeline;
  vision::VisionSettings s;
  s.paused = in.take<uint8_t>() == 0xff;
  s.mode = in.take_bool() ? vision::SearchMode::kTrackify : vision::SearchMode::kBlobify;
  s.scan = static_cast<vision::ScanMode>(in.take_in(-1, 2));
  s.threshold = in.take_bool() ? vision::kThresholdAuto : static_cast<int>(in.take_in(-2, 257));
  if (vision::check_settings(s).empty()) {
    if (!pipeline.apply(s).empty())
      ephor::fuzz::fail("settings that check_settings passed refused");
  }
  for (int k = 0; k < 4 && !in.empty(); ++k) {
    ephor::camera_frame_t f{};
    f.width = static_cast<int32_t>(in.take_in(-1, 96));
    f.height = static_cast<int32_t>(in.take_in(-1, 96));
    const int64_t pixels = f.width > 0 && f.height > 0 ? int64_t{f.width} * f.height : 0;
    f.size = static_cast<int32_t>(pixels);
    switch (in.take_in(0, 15)) {
      case 0:
        f.size = in.take<int32_t>();
        break;  // a size field that lies
      case 1:
        f.width = in.take<int32_t>();
        break;  // any width, e.g. > kMaxImageDim
      case 2:
        f.data.resize(static_cast<size_t>(in.take_in(0, 64)));
        break;  // short data
      default:
        break;
    }
    if (f.data.empty() && pixels > 0) {
      f.data.resize(static_cast<size_t>(pixels));
      for (uint8_t& p : f.data) p = in.take<uint8_t>();
    }
    // A frame check_frame() passes is searched over width * height bytes
    // of its data: ASan stops the run if the check let a short one through.
    const std::string problem = vision::check_frame(f);
    if (!problem.empty()) continue;  // refused and counted, as the process does
    const vision::ImageView view{f.data.data(), f.width, f.height, f.width};
    const vision::FrameResult r = pipeline.process(view);
    if (r.blobs == nullptr) ephor::fuzz::fail("a frame result without its blob list");
    if (r.status == vision::FrameStatus::kBadFrame && r.error.empty())
      ephor::fuzz::fail("a bad frame without a reason");
  }
  return 0;
}
