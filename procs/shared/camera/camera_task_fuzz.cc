// Fuzz target (issue 18): ephor-camera's video input (FrameSource,
// ChannelConverter and CameraTask, camera_task.h) on any file: the bytes
// written to a file clip.avi in a private temporary folder (the process
// takes a path; OpenCV's backends open files by name), opened as a
// FrameSource (which reads the first frame), the frame rate chosen as the
// process chooses it, then CameraTask::run_job() as the camera task runs it
// with the green channel (the default) and --loop (so a file's end rewinds
// it: the source opened again) until it is done, at most 40 jobs, --frames
// 30. The same FrameSource and ChannelConverter read `tools/ephor track`'s
// video (ephor-track, procs/shepherd/track).
//
// Checked: a file that cannot be opened or read is refused with a
// std::runtime_error naming it; the stated rate is 0 or finite and
// positive, the size positive; every CAMERA published has a positive size,
// width * height bytes, frame indices 0, 1, 2..., and encodes; a frame the
// converter refuses (empty, 2 channels, not 8 or 16 bits) is counted and
// not published; nothing escapes run_job().
//
// OpenCV's decoders (FFmpeg's libavformat/libavcodec, GStreamer, its own
// MJPEG reader) are third-party and not instrumented: libFuzzer sees the
// coverage of our code only, and their faults are reported as crashes too.
// OpenCV's gPhoto2 backend, which it tries on a file the others refuse,
// scans the USB bus for cameras (a fifth of a second an input) and
// libgphoto2 leaks at every scan: it is disabled here
// (OPENCV_VIDEOIO_PRIORITY_GPHOTO2=0); it never opens a file.
//
// Seeds: fuzz_corpus/video_file_camera (MJPG and raw AVI files of a few
// 32 x 24 frames, colour and grey, one 40 x 30, one cut short).

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <memory>
#include <string>
#include <system_error>
#include <vector>

#include <spdlog/spdlog.h>
#include <opencv2/core/utils/logger.hpp>

#include "common/camera/channel_converter.h"
#include "common/camera/frame_source.h"
#include "common/fuzz/fuzz_input.h"
#include "procs/shared/camera/camera_task.h"

namespace {

using namespace ephor;
using namespace ephor::camera;

constexpr int kMaxJobs = 40;
constexpr int64_t kMaxFrames = 30;  // --frames

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const bool quiet = [] {
    ::setenv("OPENCV_VIDEOIO_PRIORITY_GPHOTO2", "0", 1);
    cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_SILENT);
    spdlog::set_level(spdlog::level::off);  // the process's log (a warning per bad frame)
    return true;
  }();
  (void)quiet;
  // clip.avi in a folder of its own, made for this input and removed after
  // it (OpenCV picks its reader by the extension).
  fuzz::FuzzNamedFile video("clip.avi");
  const std::string& path = video.write(data, size);

  std::unique_ptr<FrameSource> source;
  try {
    source = std::make_unique<FrameSource>(path);
  } catch (const std::runtime_error& e) {
    if (std::string(e.what()).find(path) == std::string::npos)
      fuzz::fail(std::string("a refusal that does not name the file: ") + e.what());
    return 0;
  } catch (const std::exception& e) {
    fuzz::fail(std::string("opening threw other than std::runtime_error: ") + e.what());
  }
  if (source->kind() != SourceKind::kVideoFile) fuzz::fail("clip.avi not taken as a video file");
  const double stated = source->stated_fps();
  if (!(stated == 0.0 || (std::isfinite(stated) && stated > 0.0)))
    fuzz::fail("a stated frame rate that is neither 0 nor finite and positive");
  if (source->width() <= 0 || source->height() <= 0) fuzz::fail("an opened source of no size");

  ChannelConverter converter(ColourChannel::kGreen);
  int64_t expected_index = 0;
  bool published = false;
  CameraTask task(
      [&](camera_frame_t& m) {
        published = true;
        if (m.frame_index != expected_index++) fuzz::fail("CAMERA frame indices not 0, 1, 2...");
        if (m.width <= 0 || m.height <= 0) fuzz::fail("a CAMERA frame of no size");
        if (static_cast<int64_t>(m.width) * m.height != m.size ||
            m.data.size() != static_cast<size_t>(m.size))
          fuzz::fail("a CAMERA frame whose bytes are not width * height");
        const int n = m.getEncodedSize();
        std::vector<uint8_t> bytes(static_cast<size_t>(n));
        if (m.encode(bytes.data(), 0, n) != n) fuzz::fail("a CAMERA frame that does not encode");
      },
      *source, converter, true, kMaxFrames);
  for (int job = 0; job < kMaxJobs && !task.done(); ++job) {
    const int64_t bad_before = task.bad_frames();
    published = false;
    try {
      task.run_job();
    } catch (const std::exception& e) {
      fuzz::fail(std::string("the camera task threw: ") + e.what());
    }
    if (!task.done() && !published && task.bad_frames() != bad_before + 1)
      fuzz::fail("a frame neither published nor counted bad");
  }
  return 0;
}
