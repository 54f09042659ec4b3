#include "procs/catch/track/video_input.h"

#include <algorithm>
#include <filesystem>
#include <vector>

#include "common/catch/camera_file.h"

namespace ephor::catching {

cv::VideoCapture open_video(const std::string& path) {
  // A printf pattern is an image sequence; anything else a video file.
  // Checked first: OpenCV's backends print several lines of warnings for a
  // missing file instead of one error.
  namespace fs = std::filesystem;
  const bool pattern = path.find('%') != std::string::npos;
  if (!pattern && !fs::exists(path))
    throw VideoInputError("video file '" + path + "': no such file");
  if (!pattern && fs::is_directory(path))
    throw VideoInputError("video file '" + path + "': is a folder, not a file");
  const fs::path dir = fs::path(path).parent_path();
  if (pattern && !dir.empty() && !fs::is_directory(dir))
    throw VideoInputError("image sequence '" + path + "': no folder '" + dir.string() + "'");
  cv::VideoCapture capture;
  try {
    if (pattern)
      capture.open(path, cv::CAP_IMAGES);
    else
      capture.open(path);
  } catch (const cv::Exception& e) {
    throw VideoInputError("cannot open '" + path + "': " + e.what());
  }
  if (!capture.isOpened())
    throw VideoInputError(
        "cannot open '" + path +
        "' as a video or an image sequence (a pattern such as 'frames/%04d.png')");
  return capture;
}

cv::Mat next_frame(cv::VideoCapture& capture, int index, const std::string& video_path,
                   const CameraIntrinsics& camera, const std::string& camera_path) {
  const std::string frames_name =
      "the frames of " + video_path + " (frame " + std::to_string(index) + ")";
  // A video whose header declares another size is refused before a frame is
  // decoded: 900 bytes of AVI can declare a frame of hundreds of megabytes
  // (found by the fuzz target video_file_catch_track).
  const double declared_w = capture.get(cv::CAP_PROP_FRAME_WIDTH);
  const double declared_h = capture.get(cv::CAP_PROP_FRAME_HEIGHT);
  if (declared_w > 0.0 && declared_h > 0.0 &&
      (declared_w != camera.width || declared_h != camera.height)) {
    const auto px = [](double v) { return static_cast<int>(std::min(v, 1e9)); };
    throw VideoInputError(
        frame_size_problem(camera, camera_path, px(declared_w), px(declared_h), frames_name));
  }
  cv::Mat decoded;
  bool read = false;
  try {
    read = capture.read(decoded);
  } catch (const cv::Exception& e) {
    // OpenCV's own AVI reader asserts on a corrupt chunk (found by the fuzz
    // target video_file_catch_track).
    throw VideoInputError("frame " + std::to_string(index) + " of " + video_path +
                          ": cannot be decoded: " + e.what());
  }
  if (!read || decoded.empty()) return {};
  // The size before the conversion to grey, which would otherwise run over
  // the whole of a wrong-sized frame first.
  const std::string problem =
      frame_size_problem(camera, camera_path, decoded.cols, decoded.rows, frames_name);
  if (!problem.empty()) throw VideoInputError(problem);
  try {
    return to_grey(decoded);
  } catch (const std::invalid_argument& e) {
    throw VideoInputError("frame " + std::to_string(index) + " of " + video_path + ": " + e.what());
  }
}

BoardPoseSearch search_board_pose(
    OfflineBallTracker& tracker, int init_frames, const std::function<cv::Mat(int)>& read,
    const std::function<void(int, int, const std::string&)>& on_failed) {
  BoardPoseSearch s;
  for (;;) {
    std::vector<cv::Mat> batch;
    s.first = s.frames;
    while (static_cast<int>(batch.size()) < init_frames) {
      cv::Mat f = read(s.frames);
      if (f.empty()) break;
      batch.push_back(f.clone());
      ++s.frames;
    }
    if (batch.empty()) break;
    s.init = tracker.initialise(batch);
    if (s.init.ok) break;
    on_failed(s.first, s.frames - 1, s.init.problem);
    if (s.first_problem.empty()) s.first_problem = s.init.problem;
    if (static_cast<int>(batch.size()) < init_frames) break;  // the end of the video
  }
  return s;
}

}  // namespace ephor::catching
