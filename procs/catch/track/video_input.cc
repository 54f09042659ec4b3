#include "procs/catch/track/video_input.h"

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
  cv::Mat grey;
  try {
    grey = to_grey(decoded);
  } catch (const std::invalid_argument& e) {
    throw VideoInputError("frame " + std::to_string(index) + " of " + video_path + ": " + e.what());
  }
  const std::string problem =
      frame_size_problem(camera, camera_path, grey.cols, grey.rows,
                         "the frames of " + video_path + " (frame " + std::to_string(index) + ")");
  if (!problem.empty()) throw VideoInputError(problem);
  return grey;
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
