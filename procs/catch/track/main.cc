// ephor-catch-track: the catching system's perception offline (paper 000,
// sections 3-5.4) over a recorded video of a real board: the board's pose
// from its four circles, then the ball on the board in every frame
// (OfflineBallTracker). Run as `tools/ephor catch track`.
//
//   ephor-catch-track VIDEO|'frames/%04d.png' --board BOARD.pbtxt --camera CAMERA.pbtxt
//                     --fps F --json OUT [--circle-windows W] [--incline-deg 25]
//                     [--init-frames 10] [--no-window]
//
// OUT (JSON Lines, '-' = stdout): first
//   {"camera_pose": {"R": [9 numbers, row-major, board to camera], "t_mm": [3]},
//    "reprojection_rms_px": e, "circles_px": [[u, v] x 4], "init_frames": [first, last]}
// then one line per frame, numbered from 0, t = frame / fps:
//   {"frame": i, "t": s, "ball_mm": [x, y] or null, "status": "TRACKING", ...}
// ball_mm is the filtered ball centre in the board frame B (mm), null when no
// ball is tracked on the board. p_C = R p_B + t.
//
// The pose is looked for in the first --init-frames frames, then the next as
// many, until found: the board must stand still in them. Exit status 2 for
// bad input (a flag, a board or camera file, a video that cannot be read,
// frames of another size than the camera file's), 1 when the board's pose is
// not found anywhere in the video.

#include <fstream>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "common/catch/board_file.h"
#include "common/catch/camera_file.h"
#include "common/config/text_proto.h"
#include "procs/catch/track/offline_ball_tracker.h"
#include "procs/catch/track/video_input.h"

namespace {

using namespace ephor::catching;

constexpr const char* kName = "ephor-catch-track";

// Bad input: exit status 2 (as VideoInputError, a bad video).
struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

nlohmann::json pose_line(const TrackerInitialisation& init, int first, int last) {
  const Pose& p = init.pose.board_to_camera;
  nlohmann::json r = nlohmann::json::array(), t = nlohmann::json::array();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) r.push_back(p.linear()(i, j));
    t.push_back(p.translation()(i));
  }
  nlohmann::json circles = nlohmann::json::array();
  for (const CircleImage& c : init.circles.circles)
    circles.push_back({c.centroid_px.x(), c.centroid_px.y()});
  nlohmann::json j;
  j["camera_pose"] = {{"R", r}, {"t_mm", t}};
  j["reprojection_rms_px"] = init.pose.reprojection_rms_px;
  j["circles_px"] = circles;  // as measured, before the perspective-bias correction
  j["init_frames"] = {first, last};
  return j;
}

nlohmann::json frame_line(const TrackedFrame& f) {
  nlohmann::json j;
  j["frame"] = f.frame;
  j["t"] = f.t_s;
  j["ball_mm"] =
      f.ball_b_mm ? nlohmann::json{f.ball_b_mm->x(), f.ball_b_mm->y()} : nlohmann::json(nullptr);
  j["status"] = to_string(f.status);
  if (f.reason != RejectReason::kNone) j["reason"] = to_string(f.reason);
  j["centroid_px"] = f.centroid_px ? nlohmann::json{f.centroid_px->x(), f.centroid_px->y()}
                                   : nlohmann::json(nullptr);
  return j;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "ephor-catch-track: board pose from the four circles, then the ball on the board in every "
      "frame of a recorded video"};
  std::string video_path, board_path, camera_path, json_path, windows_text;
  int init_frames = 10;
  bool no_window = false;
  OfflineTrackerOptions options;
  app.add_option("video", video_path, "video file, or an image sequence such as 'frames/%04d.png'")
      ->required();
  app.add_option("--board", board_path, "board file (common/catch/board.proto)")->required();
  app.add_option("--camera", camera_path, "camera file (common/catch/camera.proto)")->required();
  app.add_option("--fps", options.fps, "frames per second of the recording")
      ->required()
      ->check(CLI::Range(1.0, 10000.0));
  app.add_option("--json", json_path, "output, JSON Lines ('-' = stdout)")->required();
  app.add_option("--circle-windows", windows_text,
                 "the operator's windows of interest around the four circles: 'u0,v0,u1,v1;...' "
                 "(top-left, top-right, bottom-left, bottom-right; px); default: found "
                 "automatically");
  app.add_option("--incline-deg", options.incline_deg,
                 "the board's incline (rolling acceleration and jump filter), deg")
      ->check(CLI::Range(1.0, 89.0));
  app.add_option("--init-frames", init_frames, "frames of the still board per pose attempt")
      ->check(CLI::Range(1, 1000));
  app.add_option("--window-margin-px", options.window_margin_px,
                 "window of interest: margin around the predicted ball and its motion, px")
      ->check(CLI::Range(4.0, 1000.0));
  app.add_flag("--no-window", no_window, "search the whole image every frame (the paper's way)");
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << kName << ": " << e.what() << "\n";
    return 2;
  }
  options.use_window = !no_window;

  try {
    BoardSpec board;
    CameraIntrinsics camera;
    try {
      board = load_board_file(board_path);
      camera = load_camera_file(camera_path);
      if (!windows_text.empty()) options.circle_windows = parse_circle_windows(windows_text);
    } catch (const std::exception& e) {
      throw InputError(e.what());
    }
    OfflineBallTracker tracker(board, camera, options);

    // Pass 1: the board's pose from batches of still frames.
    cv::VideoCapture capture = open_video(video_path);
    const BoardPoseSearch search = search_board_pose(
        tracker, init_frames,
        [&](int i) { return next_frame(capture, i, video_path, camera, camera_path); },
        [](int first, int last, const std::string& problem) {
          std::cerr << kName << ": frames " << first << "-" << last
                    << ": board pose not found: " << problem << "\n";
        });
    const TrackerInitialisation& init = search.init;
    const int index = search.frames, first = search.first;
    const std::string& first_problem = search.first_problem;
    if (index == 0) throw InputError("no frames in '" + video_path + "'");
    if (!init.ok) {
      std::cerr << kName << ": the board's pose was not found in any of the " << index
                << " frames of " << video_path << " (frames 0-" << std::min(index, init_frames) - 1
                << ": " << first_problem << ")\n";
      return 1;
    }
    std::cerr << kName << ": board pose from frames " << first << "-" << index - 1
              << ": reprojection " << init.pose.reprojection_rms_px << " px RMS, IPPE error ratio "
              << init.pose.ippe_error_ratio << "\n";

    std::ofstream file;
    if (json_path != "-") {
      file.open(json_path);
      if (!file) throw InputError("cannot write '" + json_path + "'");
    }
    std::ostream& out = json_path == "-" ? std::cout : file;
    out << pose_line(init, first, index - 1).dump() << "\n";

    // Pass 2: every frame from the first, through vision and the world model.
    capture = open_video(video_path);
    int frames = 0, with_ball = 0;
    for (int i = 0;; ++i) {
      const cv::Mat f = next_frame(capture, i, video_path, camera, camera_path);
      if (f.empty()) break;
      const TrackedFrame t = tracker.track(f);
      out << frame_line(t).dump() << "\n";
      ++frames;
      if (t.ball_b_mm) ++with_ball;
    }
    out.flush();
    if (!out) throw std::runtime_error("writing '" + json_path + "' failed");
    std::cerr << kName << ": " << frames << " frames, the ball on the board in " << with_ball
              << "\n";
  } catch (const InputError& e) {
    std::cerr << kName << ": " << e.what() << "\n";
    return 2;
  } catch (const VideoInputError& e) {
    std::cerr << kName << ": " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << kName << ": " << e.what() << "\n";
    return 1;
  }
  return 0;
}
