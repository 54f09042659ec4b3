// Fuzz target (issue 18): ephor-catch-track's video input (video_input.h) on
// any file: the bytes written to a file clip.avi in a private temporary
// folder (the process takes a path; OpenCV's backends open files by name),
// opened by open_video() as the process opens a video file, then pass 1 as
// the process runs it: search_board_pose() with next_frame() (8-bit grey of
// the camera's size or a refusal) and OfflineBallTracker::initialise() on
// batches of 10 frames (--init-frames' default); when a pose is found,
// pass 2: the video opened again and every frame tracked. The camera is
// 32 x 24 px (the seeds' size); the board the default one. At most 60
// frames are read per pass.
//
// Checked: a file that cannot be opened, or a frame that is not 8-bit grey
// or colour of the camera's size, is refused with a VideoInputError naming
// the file (and the frame); nothing else escapes (the process would report
// an internal error, status 1, instead of bad input, status 2); every frame
// handed on is 8-bit grey of the camera's size; a tracked ball is finite.
//
// OpenCV's decoders (FFmpeg's libavformat/libavcodec, GStreamer, its own
// MJPEG reader) are third-party and not instrumented: libFuzzer sees the
// coverage of our code only, and their faults are reported as crashes too.
// OpenCV's gPhoto2 backend, which it tries on a file the others refuse,
// scans the USB bus for cameras (a fifth of a second an input) and
// libgphoto2 leaks at every scan: it is disabled here
// (OPENCV_VIDEOIO_PRIORITY_GPHOTO2=0); it never opens a file.
//
// Seeds: fuzz_corpus/video_file_catch_track (MJPG and raw AVI files of a
// few 32 x 24 frames, colour and grey, one 40 x 30, one cut short).

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <string>
#include <system_error>

#include <opencv2/core/utils/logger.hpp>

#include "common/catch/board_model.h"
#include "common/fuzz/fuzz_input.h"
#include "procs/catch/track/offline_ball_tracker.h"
#include "procs/catch/track/video_input.h"

namespace {

using namespace ephor;
using namespace ephor::catching;

constexpr int kInitFrames = 10;  // --init-frames' default
constexpr int kMaxFrames = 60;   // per pass

void check_refusal(const VideoInputError& e, const std::string& path) {
  if (std::string(e.what()).find(path) == std::string::npos)
    fuzz::fail(std::string("a refusal that does not name the file: ") + e.what());
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const CameraIntrinsics camera = [] {
    ::setenv("OPENCV_VIDEOIO_PRIORITY_GPHOTO2", "0", 1);
    cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_SILENT);
    CameraIntrinsics c;
    c.width = 32;
    c.height = 24;
    c.fx = c.fy = 30.0;
    c.cx = 15.5;
    c.cy = 11.5;
    return c;
  }();
  static const BoardSpec board;
  // clip.avi in a folder of its own, made for this input and removed after
  // it (OpenCV picks its reader by the extension).
  fuzz::FuzzNamedFile video("clip.avi");
  const std::string& path = video.write(data, size);
  const std::string camera_path = "camera.pbtxt";

  OfflineBallTracker tracker(board, camera, OfflineTrackerOptions{});
  const auto read = [&](cv::VideoCapture& capture, int i) {
    if (i >= kMaxFrames) return cv::Mat();
    cv::Mat f = next_frame(capture, i, path, camera, camera_path);
    if (!f.empty() && (f.type() != CV_8UC1 || f.cols != camera.width || f.rows != camera.height))
      fuzz::fail("a frame handed on that is not 8-bit grey of the camera's size");
    return f;
  };
  try {
    cv::VideoCapture capture = open_video(path);
    const BoardPoseSearch search = search_board_pose(
        tracker, kInitFrames, [&](int i) { return read(capture, i); },
        [](int, int, const std::string&) {});
    if (search.frames < 0 || search.frames > kMaxFrames) fuzz::fail("frames read out of range");
    if (!search.init.ok) return 0;
    capture = open_video(path);
    for (int i = 0;; ++i) {
      const cv::Mat f = read(capture, i);
      if (f.empty()) break;
      const TrackedFrame t = tracker.track(f);
      if (t.ball_b_mm && !t.ball_b_mm->allFinite()) fuzz::fail("a tracked ball not finite");
    }
  } catch (const VideoInputError& e) {
    check_refusal(e, path);
  } catch (const std::exception& e) {
    fuzz::fail(std::string("not refused as bad input: ") + e.what());
  }
  return 0;
}
