// ephor-vision: the vision process of the shepherding system (paper sections
// 3.5 and 4.1). A periodic task at the camera rate takes the newest camera
// frame (older ones are dropped: NASREM's rule), finds its blobs with
// VisionPipeline and publishes them on BLOBS with the frame's capture time.
// VISION_CMD (full state: paused, blobify/trackify, full/axis scan,
// threshold) switches the mode at run time; the newest command wins.
//
//   ephor-vision [--period-ms 33.333] [--k 4] [--mode blobify|trackify] [--scan full|axis]
//                [--threshold -1] [--band-px 16] [--full-every 15] [--min-area 10]
//                [--foreground bright|dark|motion] [--phase-lag-ms -3] [--frame-wait-ms 8]
//                [--free-running] [--on-frame]
//
// --on-frame (deterministic replay, tools/ephor replay): the vision task is
// a triggered task released once per received frame instead of a periodic
// one, so every frame fed to it is searched (none is replaced in the mailbox
// by a newer one as long as the feeder waits for each BLOBS).

#include <chrono>
#include <cstdint>
#include <memory>
#include <string>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include "common/lcm/bus.h"
#include "common/lcm/channels.h"
#include "common/lcm/mailbox.h"
#include "common/log/log.h"
#include "common/runtime/process_args.h"
#include "common/runtime/task_runtime.h"
#include "common/shepherd/vision/vision_pipeline.h"
#include "common/time/clock.h"
#include "ephor/camera_frame_t.hpp"
#include "ephor/shepherd_blobs_t.hpp"
#include "ephor/shepherd_vision_cmd_t.hpp"
#include "procs/shepherd/vision/frame_check.h"

namespace {

using ephor::vision::FrameStatus;
using ephor::vision::ScanMode;
using ephor::vision::SearchMode;
using ephor::vision::VisionSettings;

// A camera frame and when it arrived here (for processing_us).
struct ReceivedFrame {
  ephor::camera_frame_t msg;
  int64_t received_mono_ns = 0;
};

const char* mode_name(SearchMode m) { return m == SearchMode::kTrackify ? "trackify" : "blobify"; }
const char* scan_name(ScanMode s) { return s == ScanMode::kAxis ? "axis" : "full"; }

std::string describe(const VisionSettings& s) {
  return std::string(s.paused ? "paused, " : "running, ") + mode_name(s.mode) + ", " +
         scan_name(s.scan) + " scan, threshold " +
         (s.threshold == ephor::vision::kThresholdAuto ? std::string("auto")
                                                       : std::to_string(s.threshold));
}

// The vision task: everything here runs on the task's thread, except the
// mailboxes' put() (bus thread).
class VisionTask {
 public:
  VisionTask(ephor::Bus& bus, ephor::vision::VisionPipeline& pipeline,
             std::shared_ptr<ephor::Mailbox<std::shared_ptr<const ReceivedFrame>>> frames,
             std::shared_ptr<ephor::Mailbox<ephor::shepherd_vision_cmd_t>> commands,
             std::chrono::microseconds frame_wait)
      : bus_(bus),
        pipeline_(pipeline),
        frames_(std::move(frames)),
        commands_(std::move(commands)),
        frame_wait_(frame_wait) {}

  void run_job() {
    apply_newest_command();
    // Released a little before the frame is due (--phase-lag-ms): the job
    // waits for it, briefly, rather than leaving it in the mailbox for a
    // whole period.
    const auto frame = frame_wait_.count() > 0 ? frames_->wait_take(frame_wait_) : frames_->take();
    if (!frame) return;  // no new frame since the last job
    const ephor::camera_frame_t& f = (*frame)->msg;
    std::string problem = ephor::vision::check_frame(f);
    ephor::vision::FrameResult r;
    if (problem.empty()) {
      const ephor::vision::ImageView view{f.data.data(), f.width, f.height, f.width};
      r = pipeline_.process(view);
      if (r.status == FrameStatus::kBadFrame) problem = r.error;
    }
    if (!problem.empty()) {
      ++bad_frames_;
      if (bad_frames_ <= 5 || bad_frames_ % 100 == 0) {
        spdlog::warn("skipping bad camera frame ({} so far): {}", bad_frames_, problem);
      }
      return;
    }
    if (r.threshold_picked) {
      const auto& c = pipeline_.last_threshold_choice();
      if (r.threshold_provisional) {
        spdlog::warn("threshold {} is provisional: {}", r.threshold, c.message);
      } else {
        spdlog::info("threshold {} picked from frame {} (field peak {}, mark peak {})", r.threshold,
                     f.frame_index, c.background_peak, c.object_peak);
      }
    }
    if (r.status == FrameStatus::kPaused) return;  // paused: publish nothing
    if (pipeline_.blobifier_stats().truncated) {
      ++truncated_frames_;
      if (truncated_frames_ <= 5 || truncated_frames_ % 100 == 0) {
        spdlog::warn(
            "frame {}: blob limit reached, the rest of the frame was not searched ({} "
            "such frames; noise above the threshold?)",
            f.frame_index, truncated_frames_);
      }
    }

    msg_.utime = f.utime;
    msg_.frame_index = f.frame_index;
    msg_.mode = static_cast<int8_t>(r.mode);
    msg_.scan = static_cast<int8_t>(r.scan);
    msg_.threshold = r.threshold;
    msg_.num_blobs = static_cast<int32_t>(r.blobs->size());
    msg_.blobs.resize(r.blobs->size());
    for (size_t i = 0; i < r.blobs->size(); ++i) {
      const auto& b = (*r.blobs)[i];
      msg_.blobs[i] = ephor::shepherd_blob_t{b.u, b.v, b.area, b.u_min, b.v_min, b.u_max, b.v_max};
    }
    // Frame received -> blobs ready, us (includes the wait for this job).
    msg_.processing_us = static_cast<float>(
        static_cast<double>(ephor::mono_ns() - (*frame)->received_mono_ns) / 1e3);
    bus_.publish(ephor::channels::kBlobs, msg_);
    ++published_;
    sum_processing_us_ += static_cast<double>(msg_.processing_us);
    log_status_now_and_then(r);
  }

 private:
  void apply_newest_command() {
    const auto cmd = commands_->take();
    if (!cmd) return;
    VisionSettings s;
    s.paused = cmd->paused;
    s.mode = static_cast<SearchMode>(cmd->mode);
    s.scan = static_cast<ScanMode>(cmd->scan);
    s.threshold = cmd->threshold;
    const VisionSettings before = pipeline_.settings();
    const std::string problem = pipeline_.apply(s);
    if (!problem.empty()) {
      ++bad_commands_;
      spdlog::warn("ignoring vision command from '{}' ({} so far): {}", cmd->header.sender,
                   bad_commands_, problem);
      return;
    }
    if (before.paused != s.paused || before.mode != s.mode || before.scan != s.scan ||
        before.threshold != s.threshold) {
      spdlog::info("vision mode: {} (was {})", describe(s), describe(before));
    }
  }

  void log_status_now_and_then(const ephor::vision::FrameResult& r) {
    const int64_t now = ephor::mono_ns();
    if (now - last_status_ns_ < 10'000'000'000) return;
    const double frames = static_cast<double>(published_ - published_at_status_);
    spdlog::info(
        "{} blobs in frame; {:.1f} frames/s published, mean frame-to-blobs {:.0f} us; "
        "{} frames dropped for newer, {} bad frames, {} bad commands",
        r.blobs->size(), frames / (static_cast<double>(now - last_status_ns_) / 1e9),
        frames > 0 ? sum_processing_us_ / frames : 0.0, frames_->overwritten(), bad_frames_,
        bad_commands_);
    last_status_ns_ = now;
    published_at_status_ = published_;
    sum_processing_us_ = 0.0;
  }

  ephor::Bus& bus_;
  ephor::vision::VisionPipeline& pipeline_;
  std::shared_ptr<ephor::Mailbox<std::shared_ptr<const ReceivedFrame>>> frames_;
  std::shared_ptr<ephor::Mailbox<ephor::shepherd_vision_cmd_t>> commands_;
  std::chrono::microseconds frame_wait_;
  ephor::shepherd_blobs_t msg_{};
  int64_t bad_frames_ = 0;
  int64_t bad_commands_ = 0;
  int64_t truncated_frames_ = 0;
  int64_t published_ = 0;
  int64_t published_at_status_ = 0;
  double sum_processing_us_ = 0.0;
  int64_t last_status_ns_ = 0;
};

}  // namespace

int main(int argc, char** argv) {
  ephor::block_shutdown_signals();
  CLI::App app{"ephor-vision: blobify/trackify camera frames into BLOBS"};
  ephor::ProcessArgs args;
  ephor::add_process_flags(app, args, "vision");
  double period_ms = 1000.0 / 30.0;
  double duration_s = 0.0;
  std::string mode = "blobify", scan = "full";
  bool paused = false;
  int threshold = ephor::vision::kThresholdAuto;
  ephor::vision::PipelineConfig cfg;
  app.add_option("--period-ms", period_ms,
                 "task period, ms (the camera rate; the scheduler may override it)")
      ->check(CLI::Range(0.1, 10000.0));
  app.add_option("--mode", mode, "initial search mode")
      ->check(CLI::IsMember({"blobify", "trackify"}));
  app.add_option("--scan", scan, "initial blob measurement")
      ->check(CLI::IsMember({"full", "axis"}));
  app.add_option("--threshold", threshold,
                 "grey level 1..254, or -1 = pick from the first frame's histogram");
  app.add_flag("--paused", paused, "start paused (until a VISION_CMD resumes)");
  app.add_option("--k", cfg.blobifier.sample_step, "sparse search step, px");
  app.add_option("--min-area", cfg.blobifier.min_area, "smallest blob kept, px");
  app.add_option("--max-blobs", cfg.blobifier.max_blobs, "most blobs per frame");
  app.add_option("--band-px", cfg.trackifier.band_px,
                 "trackify: border band searched for new blobs, px");
  app.add_option("--full-every", cfg.trackifier.full_every,
                 "trackify: full blobify every N frames (0 = never)");
  app.add_option("--search-radius", cfg.trackifier.search_radius_px,
                 "trackify: seed search radius, px");
  app.add_option("--fraction", cfg.threshold.fraction,
                 "threshold position between field and mark peaks (0..1)");
  app.add_option("--duration", duration_s, "exit after this many seconds (0 = until signalled)");
  // Releases are kept ahead of frame arrival and the job waits for its frame:
  // a frame that arrives up to (wait + lag) after the previous one's period
  // is still taken at once, and one late frame (the first ones at start-up)
  // does not put the next, punctual one a period behind.
  double phase_lag_ms = -3.0;
  app.add_option("--phase-lag-ms", phase_lag_ms,
                 "release the periodic task this long after each frame's arrival (negative: "
                 "before the next one is due)")
      ->check(CLI::Range(-20.0, 20.0));
  double frame_wait_ms = 8.0;
  app.add_option("--frame-wait-ms", frame_wait_ms,
                 "periodic task: wait this long for a frame not yet arrived at release (0: "
                 "do not wait)")
      ->check(CLI::Range(0.0, 30.0));
  bool free_running = false;
  app.add_flag("--free-running", free_running,
               "periodic task: keep its own phase instead of following frame arrival");
  std::string foreground = "bright";
  app.add_option("--foreground", foreground,
                 "what an object is: bright on dark (the field), dark on bright, or motion "
                 "(frame differencing)")
      ->check(CLI::IsMember({"bright", "dark", "motion"}));
  app.add_option("--background-rate", cfg.foreground.background_rate,
                 "motion: weight of the newest frame in the reference (1 = previous frame)");
  app.add_option("--motion-smooth-px", cfg.foreground.smooth_radius_px,
                 "motion: box-filter half width over the difference, px");
  bool on_frame = false;
  app.add_flag("--on-frame", on_frame,
               "one job per received frame (a triggered task; for deterministic replay) instead "
               "of the periodic task");
  if (const auto exit_status = ephor::parse_flags(app, argc, argv)) return *exit_status;
  ephor::init_logging(args.name);

  try {
    cfg.foreground.mode = ephor::vision::parse_foreground_mode(foreground);
    VisionSettings settings;
    settings.paused = paused;
    settings.mode = mode == "trackify" ? SearchMode::kTrackify : SearchMode::kBlobify;
    settings.scan = scan == "axis" ? ScanMode::kAxis : ScanMode::kFull;
    settings.threshold = threshold;
    ephor::vision::VisionPipeline pipeline(cfg, settings);  // throws naming a bad flag

    ephor::Bus bus(args.lcm_url, args.name);
    ephor::TaskRuntime runtime(bus, {args.name, args.host, !args.no_mlock});
    const int64_t lag_ns = static_cast<int64_t>(phase_lag_ms * 1e6);
    auto frames = std::make_shared<ephor::Mailbox<std::shared_ptr<const ReceivedFrame>>>();
    bus.subscribe<ephor::camera_frame_t>(
        ephor::channels::kCamera,
        [frames, &runtime, lag_ns, on_frame, free_running](const ephor::camera_frame_t& m) {
          // One copy out of LCM's decode buffer; the task then takes a pointer.
          const int64_t now = ephor::mono_ns();
          frames->put(std::make_shared<const ReceivedFrame>(ReceivedFrame{m, now}));
          if (on_frame) {
            runtime.trigger("vision");
            return;
          }
          // Keep the periodic task's phase locked to frame arrival (by default
          // released 3 ms before the next frame is due, waiting for it), so a
          // frame does not wait up to a whole period in the mailbox.
          if (!free_running) runtime.align_release("vision", now + lag_ns);
        });
    auto commands = bus.mailbox<ephor::shepherd_vision_cmd_t>(ephor::channels::kVisionCmd);

    const auto frame_wait =
        on_frame ? std::chrono::microseconds(0)
                 : std::chrono::microseconds(static_cast<int64_t>(frame_wait_ms * 1e3));
    VisionTask task(bus, pipeline, frames, commands, frame_wait);
    const auto period = std::chrono::nanoseconds(static_cast<int64_t>(period_ms * 1e6));
    if (on_frame) {
      runtime.add_triggered("vision", period, [&task] { task.run_job(); });
    } else {
      runtime.add_periodic("vision", period, [&task] { task.run_job(); });
    }
    runtime.start();
    spdlog::info("vision: {}; {} objects; k {} px, {} {:.3f} ms; {} -> {}", describe(settings),
                 foreground, cfg.blobifier.sample_step,
                 on_frame ? "one job per frame, deadline" : "period", period_ms,
                 ephor::channels::kCamera, ephor::channels::kBlobs);
    ephor::wait_for_shutdown_signal(duration_s);
    runtime.stop();
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
  return 0;
}
