// ephor-track: offline tracking of a video with the system's vision and
// world-model libraries (procs/shepherd/track/offline_tracker.h). Writes one JSON
// object per frame (JSON Lines):
//   {"frame": i, "t": s, "tracks": [{"id", "x", "y", "vx", "vy", "state"}]}
// x, y in image px (u right, v down), vx, vy in px/s, state visible /
// obscured / dead. Run through `tools/ephor track VIDEO --json FILE`.
//
//   ephor-track VIDEO --json FILE [--fps F] [--threshold T]
//               [--foreground bright|dark|motion] [--channel green|red|blue|grey] ...

#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <set>
#include <string>

#include <CLI/CLI.hpp>

#include "common/camera/channel_converter.h"
#include "common/camera/frame_source.h"
#include "common/runtime/process_args.h"
#include "procs/shepherd/track/offline_tracker.h"

int main(int argc, char** argv) {
  CLI::App app{"ephor-track: track the objects of a video offline (vision + world model)"};
  std::string video, json_path, channel = "green", foreground = "bright";
  double fps = 0.0;
  int threshold = ephor::vision::kThresholdAuto;
  int64_t max_frames = 0;
  ephor::track::OfflineTrackerConfig cfg;
  app.add_option("video", video, "video file, image-sequence pattern (frames/%04d.png)")
      ->required();
  app.add_option("--json", json_path, "output file, one JSON object per frame ('-' = stdout)")
      ->required();
  app.add_option("--fps", fps, "frame rate (default: the video's, else 30)")
      ->check(CLI::Range(0.1, 1000.0));
  app.add_option("--threshold", threshold,
                 "grey level 1..254 of the foreground image above which a pixel is object; -1 = "
                 "from the first frame's histogram");
  app.add_option("--foreground", foreground,
                 "what an object is: bright on dark, dark on bright (inverted threshold) or "
                 "motion (frame differencing)")
      ->check(CLI::IsMember({"bright", "dark", "motion"}));
  app.add_option("--background-rate", cfg.vision.foreground.background_rate,
                 "motion: weight of the newest frame in the reference (1 = previous frame)");
  app.add_option("--motion-smooth-px", cfg.vision.foreground.smooth_radius_px,
                 "motion: box-filter half width over the difference, px");
  app.add_option("--channel", channel, "8-bit channel of a colour video")
      ->check(CLI::IsMember({"green", "red", "blue", "grey"}));
  app.add_option("--k", cfg.vision.blobifier.sample_step, "sparse search step, px");
  app.add_option("--min-area", cfg.vision.blobifier.min_area, "smallest blob kept, px");
  app.add_option("--gate-px", cfg.world.visible_gate_px,
                 "association gate around a track's prediction, px");
  app.add_option("--gate-growth-px-s", cfg.world.visible_gate_growth_px_s,
                 "gate growth with the frame interval, px/s");
  app.add_option("--max-obscured-s", cfg.world.max_obscured_s,
                 "a track unseen this long is dead, s");
  app.add_option("--frames", max_frames, "stop after this many frames (0 = all)");
  if (const auto exit_status = ephor::parse_flags(app, argc, argv)) return *exit_status;

  try {
    if (threshold != ephor::vision::kThresholdAuto && (threshold < 1 || threshold > 254)) {
      throw std::invalid_argument("--threshold " + std::to_string(threshold) +
                                  " is neither 1..254 nor -1");
    }
    cfg.vision.foreground.mode = ephor::vision::parse_foreground_mode(foreground);
    cfg.settings.threshold = threshold;
    // A video that cannot be opened is bad input (status 2), as a bad flag is.
    std::unique_ptr<ephor::camera::FrameSource> opened;
    try {
      opened = std::make_unique<ephor::camera::FrameSource>(video);
    } catch (const std::exception& e) {
      throw std::invalid_argument(e.what());
    }
    ephor::camera::FrameSource& source = *opened;
    if (source.kind() == ephor::camera::SourceKind::kDevice) {
      throw std::invalid_argument("'" + video + "' is a device; track reads recorded video");
    }
    if (fps <= 0.0) fps = source.stated_fps() > 0.0 ? source.stated_fps() : 30.0;
    ephor::camera::ChannelConverter converter(ephor::camera::parse_colour_channel(channel));
    ephor::track::OfflineTracker tracker(cfg);

    std::ofstream file;
    if (json_path != "-") {
      file.open(json_path);
      if (!file) throw std::runtime_error("cannot write '" + json_path + "'");
    }
    std::ostream& out = json_path == "-" ? std::cout : file;

    cv::Mat image;
    std::vector<uint8_t> grey;
    int64_t frame = 0;
    std::set<int> ids;
    std::map<int, int> visible_frames;  // per id
    size_t most_visible = 0;
    int64_t blobs = 0;
    int last_threshold = -1;
    while ((max_frames == 0 || frame < max_frames) && source.read(image)) {
      converter.convert(image, grey);
      const ephor::vision::ImageView view{grey.data(), image.cols, image.rows, image.cols};
      const auto tracks = tracker.process(view, frame, static_cast<double>(frame) / fps);
      out << ephor::track::to_json_line(tracks) << '\n';
      size_t visible = 0;
      for (const auto& t : tracks.tracks) {
        ids.insert(t.id);
        if (t.state == ephor::worldmodel::ObjectState::kVisible) {
          ++visible;
          ++visible_frames[t.id];
        }
      }
      most_visible = std::max(most_visible, visible);
      blobs += tracks.blobs;
      last_threshold = tracks.threshold;
      ++frame;
    }
    if (!out) throw std::runtime_error("writing '" + json_path + "' failed");
    int long_tracks = 0;
    for (const auto& [id, n] : visible_frames) long_tracks += n >= fps;
    std::fprintf(stderr,
                 "ephor-track: %lld frames of %d x %d px at %.3f frames/s, %s objects, threshold "
                 "%d; %.1f blobs per frame; %zu track ids, %d visible for >= 1 s, at most %zu "
                 "visible at once -> %s\n",
                 static_cast<long long>(frame), source.width(), source.height(), fps,
                 foreground.c_str(), last_threshold,
                 frame > 0 ? static_cast<double>(blobs) / static_cast<double>(frame) : 0.0,
                 ids.size(), long_tracks, most_visible, json_path.c_str());
    if (frame == 0) throw std::runtime_error("no frame could be read from '" + video + "'");
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "ephor-track: error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ephor-track: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
