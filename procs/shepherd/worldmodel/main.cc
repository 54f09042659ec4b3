// ephor-worldmodel: blobs (BLOBS, shepherd_blobs_t) -> tracked objects (OBJECTS,
// shepherd_objects_t), paper 003 sections 4.2 and 4.3. A thin main: the work is in
// WorldModel (common/shepherd/worldmodel/world_model.h).
//
// The BLOBS subscription (bus thread) keeps the newest blobs in a mailbox
// and triggers the task "associate", which takes them, runs the four
// association stages and publishes every object with the frame's capture
// utime. Frames that arrive while a job is pending are merged (only the
// newest is processed): the paper's rule of always working on the newest
// data.
//
//   ephor-worldmodel [--calibration FILE] [--mark-height-mm Z] [process flags]

#include <atomic>
#include <cmath>
#include <iostream>
#include <memory>
#include <string>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include "common/calibration/field_calibration.h"
#include "common/config/repo_paths.h"
#include "common/config/text_proto.h"
#include "common/geometry/workcell_file.h"
#include "common/lcm/bus.h"
#include "common/lcm/channels.h"
#include "common/lcm/mailbox.h"
#include "common/log/log.h"
#include "common/runtime/process_args.h"
#include "common/runtime/task_runtime.h"
#include "common/shepherd/worldmodel/world_model.h"
#include "common/time/clock.h"
#include "ephor/shepherd_blobs_t.hpp"
#include "ephor/shepherd_objects_t.hpp"
#include "procs/shepherd/worldmodel/worldmodel_messages.h"

namespace {

using ephor::worldmodel::WorldModel;

// One job of "associate": the newest blobs -> objects.
class Associate {
 public:
  Associate(ephor::Bus& bus, WorldModel& wm,
            std::shared_ptr<ephor::Mailbox<ephor::shepherd_blobs_t>> box)
      : bus_(bus), wm_(wm), box_(std::move(box)) {}

  void operator()() {
    auto msg = box_->take();
    if (!msg) return;
    if (!ephor::worldmodel::blobs_consistent(*msg)) {
      // lcm-gen sizes the array from num_blobs, so this is a broken sender.
      spdlog::warn("BLOBS frame {}: num_blobs {} but {} blobs; ignored", msg->frame_index,
                   msg->num_blobs, msg->blobs.size());
      return;
    }
    const auto before = wm_.counters();
    const auto result = wm_.process(ephor::worldmodel::frame_of(*msg));
    const auto& after = wm_.counters();
    if (result == WorldModel::FrameResult::kDuplicate) {
      warn_every("duplicate frame (utime " + std::to_string(msg->utime) + ") ignored");
      return;
    }
    if (result == WorldModel::FrameResult::kOutOfOrder) {
      warn_every("out-of-order frame (utime " + std::to_string(msg->utime) + " older than " +
                 std::to_string(wm_.last_utime_us()) + ") ignored");
      return;
    }
    if (after.invalid_blobs != before.invalid_blobs)
      warn_every("frame " + std::to_string(msg->frame_index) + ": " +
                 std::to_string(after.invalid_blobs - before.invalid_blobs) +
                 " blob(s) with a non-finite centre or area <= 0 ignored");
    auto out = ephor::worldmodel::objects_message_of(wm_, msg->frame_index);
    bus_.publish(ephor::channels::kObjects, out);
    for (const auto& event : wm_.take_events())
      spdlog::info("{}", event);  // rare: a birth or death
    if (after.frames % 300 == 0) {
      int live = 0;
      for (const auto& o : out.objects) live += o.state != ephor::shepherd_object_t::STATE_DEAD;
      spdlog::info(
          "{} frames: {} objects live, {} created, {} died, {} re-acquired, {} merged / {} partly "
          "hidden blobs, "
          "{} duplicate / {} out-of-order frames, {} bad blobs",
          after.frames, live, after.objects_created, after.objects_died, after.reacquired,
          after.merges, after.partial_blobs, after.duplicate_frames, after.out_of_order_frames,
          after.invalid_blobs);
    }
  }

 private:
  // At most one warning per second of frames, so a broken sender cannot
  // flood the log.
  void warn_every(const std::string& text) {
    ++suppressed_;
    const int64_t now = ephor::mono_ns();
    if (now - last_warn_ns_ < 1'000'000'000) return;
    spdlog::warn("{} ({} such event(s) since the last warning)", text, suppressed_);
    suppressed_ = 0;
    last_warn_ns_ = now;
  }

  ephor::Bus& bus_;
  WorldModel& wm_;
  std::shared_ptr<ephor::Mailbox<ephor::shepherd_blobs_t>> box_;
  int64_t last_warn_ns_ = 0;
  int64_t suppressed_ = 0;
};

}  // namespace

int main(int argc, char** argv) {
  ephor::block_shutdown_signals();
  CLI::App app{"ephor-worldmodel: blobs to tracked objects (paper 003, sections 4.2-4.3)"};
  ephor::ProcessArgs args;
  ephor::add_process_flags(app, args, "worldmodel");
  std::string calibration_path;
  ephor::worldmodel::WorldModelConfig config;
  double deadline_ms = 20.0;
  app.add_option("--calibration", calibration_path,
                 "image-to-field calibration (Protobuf text); default "
                 "deploy/calibration/sim.pbtxt in the repository");
  std::string workcell_path;
  app.add_option("--workcell", workcell_path,
                 "work cell file (common/geometry/workcell.proto): the field's extent; default: "
                 "the shepherding field");
  app.add_option("--mark-height-mm", config.mark_height_mm,
                 "height in F of the sheep's marks, mm (the calibration is evaluated there)")
      ->check(CLI::Range(-1000.0, 2000.0));
  config.mark_diameter_mm = 42.0;  // the simulator's wool marks (common/shepherd/sim/world.h)
  app.add_option("--mark-diameter-mm", config.mark_diameter_mm,
                 "diameter of a whole mark, mm: a new blob much smaller is a mark still partly "
                 "under the arm and is measured once whole (0 = unknown, measure at once)")
      ->check(CLI::Range(0.0, 1000.0));
  app.add_option("--max-obscured-s", config.max_obscured_s,
                 "an object hidden this long is dropped (dead), s")
      ->check(CLI::PositiveNumber);
  app.add_option("--obscured-gate-px", config.obscured_gate_px,
                 "base radius of the gate in which a hidden object takes a blob again, px "
                 "(it grows with the time hidden)")
      ->check(CLI::Range(1.0, 500.0));
  app.add_option("--deadline-ms", deadline_ms, "deadline of the associate task, ms")
      ->check(CLI::PositiveNumber);
  if (const auto exit_status = ephor::parse_flags(app, argc, argv)) return *exit_status;
  ephor::init_logging(args.name);

  try {
    if (calibration_path.empty()) calibration_path = ephor::default_calibration_path();
    auto calibration = ephor::calibration::FieldCalibration::load(calibration_path);
    spdlog::info("calibration {} ({})", calibration_path, calibration.source());
    config.workcell = ephor::geometry::workcell_from_flag(workcell_path);
    WorldModel wm(std::move(calibration), config);

    ephor::Bus bus(args.lcm_url, args.name);
    ephor::TaskRuntime runtime(bus, {args.name, args.host, !args.no_mlock});
    auto box = std::make_shared<ephor::Mailbox<ephor::shepherd_blobs_t>>();
    runtime.add_triggered("associate",
                          std::chrono::nanoseconds(static_cast<int64_t>(deadline_ms * 1e6)),
                          Associate(bus, wm, box));
    bus.subscribe<ephor::shepherd_blobs_t>(ephor::channels::kBlobs,
                                           [box, &runtime](const ephor::shepherd_blobs_t& msg) {
                                             box->put(msg);
                                             runtime.trigger("associate");
                                           });
    runtime.start();
    spdlog::info("tracking blobs from {} -> {}", ephor::channels::kBlobs,
                 ephor::channels::kObjects);
    ephor::wait_for_shutdown_signal();
    runtime.stop();
  } catch (const ephor::ConfigError& e) {
    // A file given on the command line is bad: one line, status 2 (issue 18).
    std::cerr << "ephor-worldmodel: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
  return 0;
}
