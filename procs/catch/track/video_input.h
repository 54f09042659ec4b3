#pragma once
// ephor-catch-track's video input (out of main.cc, so that the fuzz target
// video_input_fuzz.cc runs what the process runs): the recording opened
// through OpenCV's VideoCapture, each frame checked and made 8-bit grey of
// the camera file's size, and pass 1, the board's pose from batches of
// still frames.
//
// Bad input (a video that cannot be opened, a frame of another type or
// size) is a VideoInputError naming the file and the frame: the process
// exits 2 for it.

#include <functional>
#include <stdexcept>
#include <string>

#include <opencv2/core.hpp>
#include <opencv2/videoio.hpp>

#include "common/catch/board_model.h"
#include "procs/catch/track/offline_ball_tracker.h"

namespace ephor::catching {

struct VideoInputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// A video file, or an image sequence when `path` has a '%' (a printf
// pattern such as 'frames/%04d.png'). Throws VideoInputError naming the
// path: no such file, a folder, no folder for the pattern, or neither a
// video nor an image sequence OpenCV can open.
cv::VideoCapture open_video(const std::string& path);

// The next frame as 8-bit grey of the camera's size, or an empty Mat at the
// end. Throws VideoInputError naming the frame (`index`, from 0) and the
// video for a frame of another depth, channel count or size than the camera
// file's, or one OpenCV fails to decode (a corrupt file).
cv::Mat next_frame(cv::VideoCapture& capture, int index, const std::string& video_path,
                   const CameraIntrinsics& camera, const std::string& camera_path);

// Pass 1's outcome.
struct BoardPoseSearch {
  TrackerInitialisation init;  // ok: the tracker is ready for pass 2
  int first = 0;               // index of the first frame of the last batch tried
  int frames = 0;              // frames read (the last batch's last is frames - 1)
  std::string first_problem;   // why the first batch failed, if it did
};

// Pass 1: `init_frames` frames at a time from `read` (frame index -> grey
// frame, empty at the end) until the tracker finds the board's pose in a
// batch or the video ends; `on_failed(first, last, problem)` for each batch
// that failed. Exceptions of `read` propagate.
BoardPoseSearch search_board_pose(
    OfflineBallTracker& tracker, int init_frames, const std::function<cv::Mat(int)>& read,
    const std::function<void(int, int, const std::string&)>& on_failed);

}  // namespace ephor::catching
