#include "procs/shared/camera/camera_task.h"

#include <exception>

#include <spdlog/spdlog.h>

#include "common/time/clock.h"

namespace ephor::camera {

void CameraTask::run_job() {
  if (done_) return;
  if (max_frames_ > 0 && msg_.frame_index >= max_frames_) return finish("--frames reached");
  try {
    if (!source_.read(image_)) {
      if (!loop_) return finish("end of the source");
      try {
        source_.rewind();
      } catch (const std::exception& e) {
        spdlog::error("{}", e.what());
        failed_ = true;
        return finish("cannot start the source again");
      }
      if (!source_.read(image_)) return finish("the source gave no frame after rewinding");
    }
  } catch (const std::exception& e) {
    // A frame the decoder fails on (FrameSource::read): the file is corrupt.
    spdlog::error("{}", e.what());
    failed_ = true;
    return finish("the source failed");
  }
  const int64_t capture_us = wall_us();
  try {
    converter_.convert(image_, msg_.data);
  } catch (const std::exception& e) {
    ++bad_frames_;
    if (bad_frames_ <= 5) spdlog::warn("skipping frame: {}", e.what());
    return;
  }
  msg_.utime = capture_us;
  msg_.width = image_.cols;
  msg_.height = image_.rows;
  msg_.size = static_cast<int32_t>(msg_.data.size());
  publish_(msg_);
  ++msg_.frame_index;
}

void CameraTask::finish(const char* why) {
  spdlog::info("{} frames published; stopping: {}", msg_.frame_index, why);
  done_ = true;
}

}  // namespace ephor::camera
