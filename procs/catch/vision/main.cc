// ephor-catch-vision: NASREM's Level 1-2 sensory processing for catching
// (paper 000, sections 3-5.3), the PIPE's work in software.
//
// Start-up (section 3): the four black circles are found in the first ten
// frames (CircleFinder; the operator's windows of interest can be given with
// --circle-windows), their perspective-corrected centroids give the board's
// pose in the camera frame (IPPE, both solutions checked), published on
// CATCH_BOARD_POSE and repeated every second.
//
// Then, a cyclic process at the camera rate, released by each frame (NASREM's
// rule: always the newest frame, never waiting for a particular message): Gaussian smoothing, the
// difference of two frames 1/30 s apart, threshold, centroid from the
// moments (MotionCentroid), inside a window of interest around where the
// world model predicts the ball (section 5.4's suggestion) and corrected from
// the difference blob's centroid to the ball's own centre.
//
//   subscribes  CAMERA (camera_frame_t), CATCH_WORLD (catch_world_t: the window)
//   publishes   CATCH_BOARD_POSE (catch_board_pose_t), CATCH_BALL (catch_ball_t)
//   tasks       vision (triggered by each CAMERA frame; works on the newest)

#include <algorithm>
#include <atomic>
#include <cmath>
#include <iostream>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>
#include <opencv2/core.hpp>

#include "common/catch/board_file.h"
#include "common/catch/camera_file.h"
#include "common/catch/catch_channels.h"
#include "common/catch/vision/ball_window.h"
#include "common/catch/vision/board_pose_estimator.h"
#include "common/catch/vision/circle_finder.h"
#include "common/catch/vision/motion_centroid.h"
#include "common/config/repo_paths.h"
#include "common/config/text_proto.h"
#include "common/lcm/bus.h"
#include "common/lcm/channels.h"
#include "common/lcm/mailbox.h"
#include "common/log/log.h"
#include "common/runtime/process_args.h"
#include "common/runtime/task_runtime.h"
#include "common/time/clock.h"
#include "ephor/camera_frame_t.hpp"
#include "ephor/catch_ball_t.hpp"
#include "ephor/catch_board_pose_t.hpp"
#include "ephor/catch_world_t.hpp"

namespace {

using namespace ephor;
using namespace ephor::catching;

constexpr int kInitFrames = 10;  // the paper read 10 histograms

catch_board_pose_t to_message(const CircleFinderResult& circles, const BoardPoseResult& pose) {
  catch_board_pose_t m{};
  m.utime = wall_us();
  m.valid = circles.found && pose.ok;
  m.reason = !circles.found ? circles.problem : (pose.ok ? "" : pose.problem);
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) m.r[3 * i + j] = pose.board_to_camera.linear()(i, j);
    m.t_mm[i] = pose.board_to_camera.translation()[i];
  }
  for (size_t k = 0; k < 4; ++k) {
    m.circles_px[2 * k] = circles.circles[k].centroid_px.x() - pose.bias_px[k].x();
    m.circles_px[2 * k + 1] = circles.circles[k].centroid_px.y() - pose.bias_px[k].y();
  }
  m.reprojection_rms_px = pose.reprojection_rms_px;
  m.ippe_error_ratio = pose.ippe_error_ratio;
  return m;
}

}  // namespace

int main(int argc, char** argv) {
  block_shutdown_signals();
  CLI::App app{
      "ephor-catch-vision: board pose from four circles, then the moving ball by frame "
      "differencing"};
  ProcessArgs args;
  add_process_flags(app, args, "vision");
  std::string board_path = "deploy/catch/board.pbtxt", camera_path = "deploy/catch/camera.pbtxt",
              windows_text;
  double duration_s = 0.0, window_margin_px = 24.0;
  bool no_window = false;
  app.add_option("--board", board_path, "board file (common/catch/board.proto)");
  app.add_option("--camera", camera_path, "camera file (common/catch/camera.proto)");
  app.add_option(
      "--circle-windows", windows_text,
      "the operator's windows of interest around the four circles: 'u0,v0,u1,v1;...' "
      "(top-left, top-right, bottom-left, bottom-right; px); default: found automatically");
  app.add_option("--window-margin-px", window_margin_px,
                 "window of interest: margin around the predicted ball and its motion, px")
      ->check(CLI::Range(4.0, 1000.0));
  app.add_flag("--no-window", no_window, "search the whole image every frame (the paper's way)");
  app.add_option("--duration", duration_s, "exit after this many seconds (0 = until signalled)");
  if (const auto exit_status = ephor::parse_flags(app, argc, argv)) return *exit_status;
  init_logging(args.name);

  try {
    const BoardSpec board = load_board_file(resolve_repo_path(board_path));
    const CameraIntrinsics intrinsics = load_camera_file(resolve_repo_path(camera_path));
    CircleFinderOptions finder_options;
    if (!windows_text.empty()) finder_options.windows = parse_circle_windows(windows_text);
    const CircleFinder finder(board, intrinsics, finder_options);
    const BoardPoseEstimator estimator(board, intrinsics);
    MotionCentroid motion;

    Bus bus(args.lcm_url, args.name);
    TaskRuntime runtime(bus, {args.name, args.host, !args.no_mlock});
    Mailbox<camera_frame_t> frames;
    Mailbox<catch_world_t> worlds;
    std::atomic<int64_t> bad_frames{0}, published{0};
    bus.subscribe<camera_frame_t>(ephor::channels::kCamera, [&](const camera_frame_t& m) {
      frames.put(m);
      runtime.trigger("vision");
    });
    bus.subscribe<catch_world_t>(catching::channels::kWorld,
                                 [&](const catch_world_t& m) { worlds.put(m); });

    std::vector<cv::Mat> init_frames;
    std::optional<catch_board_pose_t> pose_msg;
    std::optional<BoardPoseResult> pose;
    int64_t last_pose_sent_us = 0;
    int64_t last_frame_index = -1;

    // The window of interest for a frame captured at `utime`: around the
    // world model's newest ball position carried forward to that time.
    std::optional<BallWindow> ball_window;
    auto window_for = [&](int64_t utime) -> std::optional<cv::Rect> {
      if (no_window || !ball_window) return std::nullopt;
      const auto w = worlds.latest();
      if (!w || w->status != catch_world_t::STATUS_TRACKING) return std::nullopt;
      return ball_window->around(Eigen::Vector2d(w->position_b_mm[0], w->position_b_mm[1]),
                                 Eigen::Vector2d(w->velocity_b_mm_s[0], w->velocity_b_mm_s[1]),
                                 static_cast<double>(utime - w->utime) / 1e6);
    };

    // Released by each frame's arrival (the PIPE ran on the video clock):
    // the job always takes the newest frame, so a late job skips, never queues.
    runtime.add_triggered("vision", std::chrono::milliseconds(16), [&] {
      const auto frame = frames.take();
      if (!frame) return;
      if (frame->width != intrinsics.width || frame->height != intrinsics.height ||
          frame->size != frame->width * frame->height ||
          frame->data.size() != static_cast<size_t>(frame->size)) {
        if (++bad_frames % 60 == 1)
          spdlog::error(
              "CAMERA frame {} is {} x {} ({} bytes); the camera file says {} x {}: "
              "ignored ({} so far)",
              frame->frame_index, frame->width, frame->height, frame->data.size(), intrinsics.width,
              intrinsics.height, bad_frames.load());
        return;
      }
      const cv::Mat image(frame->height, frame->width, CV_8UC1,
                          const_cast<uint8_t*>(frame->data.data()));
      if (!pose) {
        init_frames.push_back(image.clone());
        if (static_cast<int>(init_frames.size()) < kInitFrames) return;
        const CircleFinderResult circles = finder.find(init_frames);
        init_frames.clear();
        BoardPoseResult p;
        if (circles.found) {
          std::array<Eigen::Vector2d, 4> c;
          for (size_t k = 0; k < 4; ++k) c[k] = circles.circles[k].centroid_px;
          p = estimator.estimate(c);
        }
        pose_msg = to_message(circles, p);
        bus.publish(catching::channels::kBoardPose, *pose_msg);
        if (!pose_msg->valid) {
          spdlog::error("board pose not found ({}); trying again with the next {} frames",
                        pose_msg->reason, kInitFrames);
          return;
        }
        pose = p;
        ball_window.emplace(board, intrinsics, p.board_to_camera,
                            BallWindowOptions{window_margin_px, 1.0 / 30.0, 0.1});
        last_pose_sent_us = wall_us();
        spdlog::info(
            "board pose from the circles: reprojection {:.3f} px RMS, IPPE error ratio "
            "{:.1f}; perspective bias {:.2f} {:.2f} {:.2f} {:.2f} px",
            p.reprojection_rms_px, p.ippe_error_ratio, p.bias_px[0].norm(), p.bias_px[1].norm(),
            p.bias_px[2].norm(), p.bias_px[3].norm());
        return;
      }
      if (wall_us() - last_pose_sent_us > 1'000'000) {
        pose_msg->utime = wall_us();
        bus.publish(catching::channels::kBoardPose, *pose_msg);
        last_pose_sent_us = pose_msg->utime;
      }
      if (last_frame_index >= 0 && frame->frame_index != last_frame_index + 1) motion.reset();
      last_frame_index = frame->frame_index;
      const auto window = window_for(frame->utime);
      const MotionMeasurement m = motion.process(image, window);
      catch_ball_t out{};
      out.utime = frame->utime;
      out.frame_index = frame->frame_index;
      out.found = m.found;
      out.u = static_cast<float>(m.centroid_px.x());
      out.v = static_cast<float>(m.centroid_px.y());
      out.u_blob = static_cast<float>(m.plain_centroid_px.x());
      out.v_blob = static_cast<float>(m.plain_centroid_px.y());
      out.area_px = static_cast<int32_t>(m.area_px);
      const cv::Rect w = window.value_or(cv::Rect(0, 0, intrinsics.width, intrinsics.height));
      out.window[0] = static_cast<int16_t>(w.x);
      out.window[1] = static_cast<int16_t>(w.y);
      out.window[2] = static_cast<int16_t>(w.x + w.width - 1);
      out.window[3] = static_cast<int16_t>(w.y + w.height - 1);
      out.exec_ms = static_cast<float>(m.elapsed_ms);
      bus.publish(catching::channels::kBall, out);
      ++published;
    });

    runtime.start();
    spdlog::info("ready: finding the board's four circles in the first {} frames", kInitFrames);
    wait_for_shutdown_signal(duration_s);
    runtime.stop();
    spdlog::info("summary: {} ball messages, {} bad frames", published.load(), bad_frames.load());
  } catch (const ephor::ConfigError& e) {
    // A file given on the command line is bad: one line, status 2 (issue 18).
    std::cerr << "ephor-catch-vision: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
  return 0;
}
