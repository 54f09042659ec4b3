// ephor-stripe-calibrate: the `calibrate` process of the light-stripe system
// (paper 004, sections 3-4, and one joint refinement beyond the paper): runs
// the calibration procedure (calibration_run.h) through the running system -
// each view a joint goal to the shared arm through comm (ARM_GOAL, waiting
// for its MOTION_DONE), then an image at rest (STRIPE_CAPTURE ->
// STRIPE_IMAGE, with the joint readings of that instant, which the fits use)
// - and writes the calibration file (Protobuf text,
// common/stripe/stripe_calibration.proto) for the range process and the
// scan planner. Each step's correction is logged as it ends, as the paper's
// program printed them, and kept in the file's report.
//
//   ephor-stripe-calibrate --robot-seed N --out FILE [--from FILE] [--views full|quick]
//                          [--all-branches] [--no-links]
//
//   subscribes  ARM_STATE, MOTION_DONE, STRIPE_IMAGE
//   publishes   ARM_GOAL (arm_goal_t, KIND_JOINTS), STRIPE_CAPTURE
//
// Ends (exit 0) when the file is written; 1 when the calibration fails; 2 on
// bad input (one line; nothing has moved).

#include <atomic>
#include <condition_variable>
#include <filesystem>
#include <iostream>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include "common/config/repo_paths.h"
#include "common/config/text_proto.h"
#include "common/geometry/workcell_file.h"
#include "common/lcm/bus.h"
#include "common/lcm/channels.h"
#include "common/log/log.h"
#include "common/runtime/process_args.h"
#include "common/stripe/calibration_file.h"
#include "common/stripe/stripe_channels.h"
#include "common/stripe/stripe_messages.h"
#include "common/time/clock.h"
#include "ephor/arm_goal_t.hpp"
#include "ephor/arm_state_t.hpp"
#include "ephor/motion_done_t.hpp"
#include "ephor/stripe_capture_t.hpp"
#include "ephor/stripe_image_t.hpp"
#include "procs/stripe/calibrate/calibration_run.h"
#include "procs/stripe/calibrate/rig_messages.h"

namespace {

using namespace ephor;
using namespace ephor::stripe;

class Stopped : public std::runtime_error {
 public:
  Stopped() : std::runtime_error("stopped") {}
};

// The rig of the running system: the shared arm through comm, the camera
// through the simulator (or a real camera publishing STRIPE_IMAGE).
class BusRig : public CalibrationRig {
 public:
  BusRig(Bus& bus, std::string name, const std::atomic<bool>& stop)
      : bus_(bus), inbox_(std::move(name)), stop_(stop) {
    bus_.subscribe<arm_state_t>(ephor::channels::kArmState, [this](const arm_state_t& m) {
      std::lock_guard<std::mutex> lock(mutex_);
      if (inbox_.on_arm_state(m)) spdlog::info("the arm is heard");
      cv_.notify_all();
    });
    bus_.subscribe<motion_done_t>(ephor::channels::kMotionDone, [this](const motion_done_t& m) {
      std::lock_guard<std::mutex> lock(mutex_);
      if (inbox_.on_motion_done(m)) cv_.notify_all();
    });
    bus_.subscribe<stripe_image_t>(stripe::channels::kImage, [this](const stripe_image_t& m) {
      std::lock_guard<std::mutex> lock(mutex_);
      if (inbox_.on_image(m)) cv_.notify_all();
    });
  }

  cv::Mat stripe_image(const arm::Joints& q) override {
    return take(q, stripe_capture_t::MODE_STRIPE);
  }
  cv::Mat spot_image(const arm::Joints& q) override { return take(q, stripe_capture_t::MODE_SPOT); }
  arm::Joints readings(const arm::Joints&) const override { return last_q_; }

  // Waits for the arm's state (comm holds goals until it has heard it too).
  void wait_for_arm() {
    std::unique_lock<std::mutex> lock(mutex_);
    while (!inbox_.arm_heard()) wait(lock, 1.0);
  }

  int skipped() const { return skipped_; }
  double motion_s() const { return motion_s_; }

 private:
  // Caller holds the lock; throws Stopped when asked to stop.
  void wait(std::unique_lock<std::mutex>& lock, double s) {
    cv_.wait_for(lock, std::chrono::duration<double>(s));
    if (stop_) throw Stopped();
  }

  cv::Mat take(const arm::Joints& q, int8_t mode) {
    const double t0 = static_cast<double>(mono_ns()) * 1e-9;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      arm_goal_t g = inbox_.next_goal(q, wall_us());
      bus_.publish(ephor::channels::kArmGoal, g);
      const int64_t give_up = mono_ns() + 120'000'000'000LL;
      while (!inbox_.done()) {
        if (mono_ns() > give_up)
          throw CalibrationError("no MOTION_DONE for view " + std::to_string(inbox_.goal_id()) +
                                 " in 120 s (are comm and the arm running?)");
        wait(lock, 0.2);
      }
      motion_s_ += static_cast<double>(mono_ns()) * 1e-9 - t0;
      if (!inbox_.view_reached()) {
        // Out of the arm's reach or colliding by its own checks: no view.
        ++skipped_;
        spdlog::warn("view {} skipped: the arm refused it: {}", inbox_.goal_id(),
                     inbox_.done()->reason);
        last_q_ = q;
        return cv::Mat(256, 256, CV_8UC1, cv::Scalar(0));
      }
    }
    for (int attempt = 0; attempt < 10; ++attempt) {
      std::unique_lock<std::mutex> lock(mutex_);
      stripe_capture_t c = inbox_.next_capture(mode, wall_us());
      bus_.publish(stripe::channels::kCapture, c);
      const int64_t give_up = mono_ns() + 1'000'000'000LL;
      while (!inbox_.image() && mono_ns() < give_up) wait(lock, 0.05);
      if (!inbox_.image()) continue;
      return inbox_.view_image(&last_q_);
    }
    throw CalibrationError("no image from the camera for view " + std::to_string(inbox_.goal_id()) +
                           " after 10 requests (is the simulator running?)");
  }

  Bus& bus_;
  RigInbox inbox_;
  const std::atomic<bool>& stop_;
  std::mutex mutex_;
  std::condition_variable cv_;
  arm::Joints last_q_ = arm::Joints::Zero();
  int skipped_ = 0;
  double motion_s_ = 0.0;
};

}  // namespace

int main(int argc, char** argv) {
  block_shutdown_signals();
  CLI::App app{
      "ephor-stripe-calibrate: the light-stripe sensor's calibration through the running system"};
  ProcessArgs args;
  add_process_flags(app, args, "calibrate");
  int robot_seed = 0;
  std::string out_path, from_path, views = "full", workcell_path = "deploy/stripe/workcell.pbtxt";
  bool all_branches = false, no_links = false;
  double spot_x = 0.0, spot_y = 0.0;
  app.add_option("--robot-seed", robot_seed, "the robot being calibrated (the file is for it)")
      ->check(CLI::Range(0, 1000000));
  app.add_option("--out", out_path, "write the calibration file here")->required();
  app.add_option("--from", from_path,
                 "start from this calibration file of the robot (default: the nominal arm and "
                 "the cage from the drawings)");
  app.add_option("--views", views, "full (default: a few minutes) or quick (under a minute)");
  app.add_flag("--all-branches", all_branches,
               "section 3's views in every arm branch (righty / lefty, elbow, wrist flip), for an "
               "arm that goes to a joint goal in the configuration asked for");
  app.add_flag("--no-links", no_links,
               "the refinement fits the paper's model only (zero references, C_T, light plane)");
  app.add_option("--spot-x-mm", spot_x, "where the table's spot is believed to be, x (mm)");
  app.add_option("--spot-y-mm", spot_y, "... y (mm)");
  app.add_option("--workcell", workcell_path,
                 "work cell file (default deploy/stripe/workcell.pbtxt)");
  if (const auto exit_status = ephor::parse_flags(app, argc, argv)) return *exit_status;

  CalibrationRunOptions options;
  geometry::Workcell workcell;
  StripeCalibration start;
  try {
    options.views = parse_calibration_views(views);
    options.all_branches = all_branches;
    options.link_errors = !no_links;
    options.spot_guess_mm = Eigen::Vector2d(spot_x, spot_y);
    workcell = geometry::load_workcell_file(resolve_repo_path(workcell_path));
    start = calibration_from_flags(from_path, robot_seed);
    const std::filesystem::path out(out_path);
    const std::filesystem::path dir =
        out.has_parent_path() ? out.parent_path() : std::filesystem::path(".");
    if (std::filesystem::is_directory(out))
      throw std::invalid_argument("--out " + out_path + " is a folder, not a file");
    if (!std::filesystem::is_directory(dir))
      throw std::invalid_argument("--out " + out_path + ": folder " + dir.string() +
                                  " does not exist");
  } catch (const std::exception& e) {
    std::cerr << "ephor-stripe-calibrate: " << e.what() << "\n";
    return 2;
  }
  init_logging(args.name);

  try {
    Bus bus(args.lcm_url, args.name);
    std::atomic<bool> stop{false}, finished{false};
    BusRig rig(bus, args.name, stop);
    bus.start();
    int exit_code = 0;
    std::thread worker([&] {
      try {
        spdlog::info("waiting for the arm; then {} views from {}", to_string(options.views),
                     start.measured);
        rig.wait_for_arm();
        const int64_t t0 = mono_ns();
        const CalibrationRunResult r =
            run_calibration(rig, StripeWorkcell::from_workcell(workcell), start, options,
                            [](const std::string& line) { spdlog::info("{}", line); });
        StripeCalibration c = r.calibration;
        const double s = static_cast<double>(mono_ns() - t0) * 1e-9;
        c.measured = fmt::format(
            "ephor-stripe-calibrate --views {}{}{} on robot seed {}, {} images in {:.0f} s ({} "
            "views the arm refused), from {}",
            to_string(options.views), all_branches ? " --all-branches" : "",
            no_links ? " --no-links" : "", robot_seed, r.views, s, rig.skipped(), start.measured);
        save_stripe_calibration(out_path, c);
        spdlog::info("calibration written to {}: {} images in {:.1f} s, the arm moving {:.1f} s",
                     out_path, r.views, s, rig.motion_s());
      } catch (const Stopped&) {
        spdlog::warn("stopped before the calibration was finished; nothing written");
        exit_code = 1;
      } catch (const std::exception& e) {
        spdlog::error("calibration failed: {}", e.what());
        exit_code = 1;
      }
      finished = true;
    });
    while (!finished) {
      if (wait_for_shutdown_signal(0.05) != 0) {
        stop = true;
        break;
      }
    }
    worker.join();
    bus.stop();
    return exit_code;
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
}
