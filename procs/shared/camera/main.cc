// ephor-camera: a real camera for the system. Publishes CAMERA
// (camera_frame_t, the same message as ephor-sim's camera, so ephor-vision
// cannot tell them apart) from a video file, an image sequence
// (frames/%04d.png) or a V4L2 device through OpenCV's VideoCapture,
// converting each frame to one 8-bit channel (green by default, as the
// paper's digitiser).
//
//   ephor-camera SOURCE [--fps F] [--channel green|red|blue|grey] [--loop] [--frames N]
//
// One periodic task "camera" at the frame rate (the file's stated rate, or
// --fps; 30 Hz when neither says). A frame's utime is the wall clock when
// it was read (its capture time for a device). At the end of a file or
// sequence the process exits with status 0, or starts again with --loop.
// A source that cannot be opened: one line naming it, exit 2 (bad input);
// one that fails later: a message naming it, exit 1.

#include <sys/types.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <iostream>
#include <memory>
#include <string>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include "common/camera/channel_converter.h"
#include "common/camera/frame_source.h"
#include "common/lcm/bus.h"
#include "common/lcm/channels.h"
#include "common/log/log.h"
#include "common/runtime/process_args.h"
#include "common/runtime/task_runtime.h"
#include "ephor/camera_frame_t.hpp"
#include "procs/shared/camera/camera_task.h"

int main(int argc, char** argv) {
  ephor::block_shutdown_signals();
  CLI::App app{"ephor-camera: frames from a video file, image sequence or V4L2 device -> CAMERA"};
  ephor::ProcessArgs args;
  ephor::add_process_flags(app, args, "camera");
  std::string spec, channel = "green";
  double fps = 0.0;
  bool loop = false;
  int64_t max_frames = 0;
  app.add_option("source", spec,
                 "video file, image-sequence pattern (frames/%04d.png) or device (/dev/video0)")
      ->required();
  app.add_option("--fps", fps, "frames per second (default: the source's rate, else 30)")
      ->check(CLI::Range(0.1, 1000.0));
  app.add_option("--channel", channel, "8-bit channel published (the paper used green)")
      ->check(CLI::IsMember({"green", "red", "blue", "grey"}));
  app.add_flag("--loop", loop, "start a file or sequence again at its end");
  app.add_option("--frames", max_frames, "stop after this many frames (0 = all)")
      ->check(CLI::NonNegativeNumber);
  if (const auto exit_status = ephor::parse_flags(app, argc, argv)) return *exit_status;
  ephor::init_logging(args.name);

  // A source that cannot be opened is bad input: one line, status 2 (issue 18).
  std::unique_ptr<ephor::camera::FrameSource> opened;
  try {
    opened = std::make_unique<ephor::camera::FrameSource>(spec);
  } catch (const std::exception& e) {
    std::cerr << "ephor-camera: " << e.what() << "\n";
    return 2;
  }
  try {
    ephor::camera::FrameSource& source = *opened;
    ephor::camera::ChannelConverter converter(ephor::camera::parse_colour_channel(channel));
    if (fps <= 0.0) fps = source.stated_fps() > 0.0 ? source.stated_fps() : 30.0;

    ephor::Bus bus(args.lcm_url, args.name);
    ephor::TaskRuntime runtime(bus, {args.name, args.host, !args.no_mlock});
    ephor::camera::CameraTask task(
        [&bus](ephor::camera_frame_t& m) { bus.publish(ephor::channels::kCamera, m); }, source,
        converter, loop, max_frames);
    runtime.add_periodic("camera", std::chrono::nanoseconds(static_cast<int64_t>(1e9 / fps)),
                         [&task] { task.run_job(); });
    runtime.start();
    spdlog::info("{} '{}': {} x {} px, {} channel, {:.3f} frames/s{} -> {}",
                 ephor::camera::source_kind_name(source.kind()), spec, source.width(),
                 source.height(), channel, fps, loop ? ", looping" : "", ephor::channels::kCamera);
    while (!task.done()) {
      if (ephor::wait_for_shutdown_signal(0.1) != 0) break;
    }
    runtime.stop();
    if (task.failed()) return 1;
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
  return 0;
}
