#pragma once
// CameraTask: ephor-camera's one job, the next frame -> CAMERA (out of
// main.cc, so that the fuzz target camera_task_fuzz.cc runs what the
// process runs): a frame read from the FrameSource (rewound at the end with
// --loop), converted to one 8-bit channel by the ChannelConverter and handed
// to `publish` as camera_frame_t. A frame the converter refuses (empty, 2
// channels, float pixels...) is counted in bad_frames(), logged (the first
// five) and skipped; nothing is published for it.
//
// Threading: run_job() on the camera task's thread; done(), failed() from
// any thread.

#include <atomic>
#include <cstdint>
#include <functional>
#include <utility>

#include <opencv2/core.hpp>

#include "common/camera/channel_converter.h"
#include "common/camera/frame_source.h"
#include "ephor/camera_frame_t.hpp"

namespace ephor::camera {

class CameraTask {
 public:
  using Publish = std::function<void(camera_frame_t&)>;  // the bus stamps its header

  // max_frames: stop after this many frames published (0 = all).
  CameraTask(Publish publish, FrameSource& source, ChannelConverter& converter, bool loop,
             int64_t max_frames)
      : publish_(std::move(publish)),
        source_(source),
        converter_(converter),
        loop_(loop),
        max_frames_(max_frames) {}

  // One frame: read, convert, publish (utime: the wall clock when read).
  void run_job();

  bool done() const { return done_; }
  // The source failed: a frame it could not decode, or it could not be
  // started again for --loop (the process exits 1).
  bool failed() const { return failed_; }
  int64_t published() const { return msg_.frame_index; }
  int64_t bad_frames() const { return bad_frames_; }

 private:
  void finish(const char* why);

  Publish publish_;
  FrameSource& source_;
  ChannelConverter& converter_;
  bool loop_;
  int64_t max_frames_;
  cv::Mat image_;
  camera_frame_t msg_{};
  int64_t bad_frames_ = 0;
  std::atomic<bool> done_{false};
  std::atomic<bool> failed_{false};
};

}  // namespace ephor::camera
