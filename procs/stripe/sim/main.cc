// ephor-stripe-sim: the light-stripe system's world (paper 004, sections 2-3),
// in real time: the PUMA 560 as it really is (TrueArm: the robot seed's joint
// zero-reference and link errors), following ephor-arm's trajectories
// through the simulated servo layer (ArmServo, in joint readings, as every
// system's simulator does), the sensor cage on its flange as it really is
// (the seed's C_T, S_T), the scene on the table, and the camera: on each
// STRIPE_CAPTURE, once the arm is at rest, the image rendered by ray casting
// (the stripe with the infrared filter, or the table's spot with it removed)
// with its capture time and the joint readings of that instant. The truth
// goes on its own channel; nothing else about it leaves the process.
//
//   ephor-stripe-sim [--robot-seed N] [--scene FILE.obj] [--workcell FILE] [--seed S]
//
//   subscribes  ARM_TRAJECTORY (joint_trajectory_t), STRIPE_CAPTURE (stripe_capture_t)
//   publishes   ARM_SERVO (joint_state_t, 250 Hz), STRIPE_IMAGE (stripe_image_t),
//               STRIPE_CAMERA (camera_frame_t: each image again, for the page),
//               STRIPE_TRUTH (stripe_truth_t: with each image and once a second)
//   tasks       physics (2 ms: the servo in 1 ms steps), camera (triggered by a
//               capture request), truth (1 s)
//
// A repeated request (the same requester and request id as the last one
// answered for that requester) is answered with the same image again.

#include <atomic>
#include <cmath>
#include <iostream>
#include <mutex>
#include <optional>
#include <string>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include "common/arm/arm_workcell.h"
#include "common/arm/servo_messages.h"
#include "common/config/repo_paths.h"
#include "common/config/text_proto.h"
#include "common/geometry/workcell_file.h"
#include "common/lcm/bus.h"
#include "common/lcm/channels.h"
#include "common/log/log.h"
#include "common/runtime/process_args.h"
#include "common/runtime/task_runtime.h"
#include "common/stripe/stripe_channels.h"
#include "common/stripe/stripe_messages.h"
#include "common/stripe/stripe_world.h"
#include "common/time/clock.h"
#include "ephor/camera_frame_t.hpp"
#include "ephor/joint_state_t.hpp"
#include "ephor/joint_trajectory_t.hpp"
#include "ephor/stripe_capture_t.hpp"
#include "ephor/stripe_image_t.hpp"
#include "ephor/stripe_truth_t.hpp"
#include "procs/stripe/sim/sim_messages.h"

namespace {

using namespace ephor;
using namespace ephor::stripe;

}  // namespace

int main(int argc, char** argv) {
  block_shutdown_signals();
  CLI::App app{
      "ephor-stripe-sim: the light-stripe system's world: the true arm, the cage, the scene, the "
      "camera"};
  ProcessArgs args;
  add_process_flags(app, args, "sim");
  int robot_seed = 0;
  uint64_t seed = 1;
  std::string scene_path, workcell_path = "deploy/stripe/workcell.pbtxt";
  double settle_ms = 300.0, duration_s = 0.0;
  app.add_option("--robot-seed", robot_seed,
                 "the robot: its joint zero-reference and link errors and its cage's (0 = an "
                 "ideal robot; default 0)")
      ->check(CLI::Range(0, 1000000));
  app.add_option("--scene", scene_path,
                 "scene file (Wavefront OBJ, mm, table frame; default: the empty table)");
  app.add_option("--workcell", workcell_path,
                 "work cell file (common/geometry/workcell.proto; default "
                 "deploy/stripe/workcell.pbtxt)");
  app.add_option("--seed", seed, "image noise seed (default 1)");
  app.add_option("--settle-ms", settle_ms,
                 "longest wait for the arm to come to rest before an image, ms (default 300)")
      ->check(CLI::Range(0.0, 10000.0));
  app.add_option("--duration", duration_s, "exit after this many seconds (0 = until signalled)")
      ->check(CLI::Range(0.0, 1e7));
  if (const auto exit_status = ephor::parse_flags(app, argc, argv)) return *exit_status;
  init_logging(args.name);

  try {
    const geometry::Workcell workcell =
        geometry::load_workcell_file(resolve_repo_path(workcell_path));
    const StripeScene scene =
        scene_path.empty() ? StripeScene() : StripeScene::load(resolve_repo_path(scene_path));
    const RobotTruth truth = robot_seed == 0 ? RobotTruth::ideal() : RobotTruth::draw(robot_seed);
    const StripeWorld world(scene, StripeWorkcell::from_workcell(workcell), truth);
    std::mutex servo_mutex;
    SimServo servo(arm::make_puma(workcell).limits());
    int64_t mono0_ns = 0;
    auto advance_to_now = [&] {  // caller holds servo_mutex
      servo.advance_to(static_cast<double>(mono_ns() - mono0_ns) * 1e-9);
    };

    Bus bus(args.lcm_url, args.name);
    TaskRuntime runtime(bus, {args.name, args.host, !args.no_mlock});
    std::mutex capture_mutex;
    CaptureDesk desk;
    std::atomic<int64_t> images{0}, repeats{0}, refused{0}, refused_captures{0};

    bus.subscribe<joint_trajectory_t>(
        ephor::channels::kArmTrajectory, [&](const joint_trajectory_t& m) {
          std::string why;
          std::lock_guard<std::mutex> lock(servo_mutex);
          if (!servo.on_trajectory(m, &why)) {
            ++refused;
            spdlog::warn("ARM_TRAJECTORY seq {} ignored: {}", m.seq, why);
          }
        });
    bus.subscribe<stripe_capture_t>(stripe::channels::kCapture, [&](const stripe_capture_t& m) {
      {
        std::string why;
        std::lock_guard<std::mutex> lock(capture_mutex);
        if (!desk.on_capture(m, &why)) {
          ++refused_captures;
          spdlog::warn("STRIPE_CAPTURE from {} ignored: {}", m.header.sender, why);
          return;
        }
      }
      runtime.trigger("camera");
    });

    mono0_ns = mono_ns();
    runtime.add_periodic("physics", std::chrono::milliseconds(2), [&] {
      joint_state_t m;
      {
        std::lock_guard<std::mutex> lock(servo_mutex);
        advance_to_now();
        if (!servo.servo_tick()) return;  // ARM_SERVO at 250 Hz
        m = sim::to_joint_state(servo.state(), wall_us());
      }
      bus.publish(ephor::channels::kArmServo, m);
    });

    runtime.add_triggered("camera", std::chrono::milliseconds(500), [&] {
      for (;;) {
        stripe_capture_t req;
        {
          std::lock_guard<std::mutex> lock(capture_mutex);
          std::optional<stripe_capture_t> next = desk.next();
          if (!next) return;
          req = std::move(*next);
          if (const stripe_image_t* answer = desk.repeat_of(req)) {
            ++repeats;
            stripe_image_t again = *answer;
            bus.publish(stripe::channels::kImage, again);
            continue;
          }
        }
        // At rest first (a camera on a moving arm would blur), at most settle_ms.
        arm::Joints q;
        const int64_t give_up = mono_ns() + static_cast<int64_t>(settle_ms * 1e6);
        for (;;) {
          bool rest = false;
          {
            std::lock_guard<std::mutex> lock(servo_mutex);
            advance_to_now();
            q = servo.state().q;
            rest = servo.at_rest();
          }
          if (rest || mono_ns() >= give_up) break;
          sleep_until_mono_ns(mono_ns() + 1'000'000);
        }
        const int64_t utime = wall_us();
        const int64_t index = images++;
        const std::uint64_t image_seed = seed * 1000003ULL + static_cast<std::uint64_t>(index);
        const cv::Mat img = req.mode == stripe_capture_t::MODE_SPOT
                                ? world.spot_image(q, image_seed)
                                : world.image(q, image_seed);
        stripe_image_t m = image_message_of(req, img, q, utime, index);
        bus.publish(stripe::channels::kImage, m);
        camera_frame_t frame = camera_frame_of(m);  // the same pixels for pages and lcm-spy
        bus.publish(stripe::channels::kCamera, frame);
        stripe_truth_t t = truth_message(world, robot_seed, scene_path, q, utime, index);
        bus.publish(stripe::channels::kTruth, t);
        std::lock_guard<std::mutex> lock(capture_mutex);
        desk.answered(m);
      }
    });

    runtime.add_periodic("truth", std::chrono::seconds(1), [&] {
      arm::Joints q;
      {
        std::lock_guard<std::mutex> lock(servo_mutex);
        q = servo.state().q;
      }
      stripe_truth_t t = truth_message(world, robot_seed, scene_path, q, wall_us(), -1);
      bus.publish(stripe::channels::kTruth, t);
    });

    runtime.start();
    spdlog::info(
        "ready: robot seed {} (zero references off by up to {:.2f} deg), scene {} ({} triangles), "
        "arm at its start configuration",
        robot_seed, truth.arm.errors().zero_offset_rad.cwiseAbs().maxCoeff() * 180.0 / M_PI,
        scene_path.empty() ? "the empty table" : scene_path, scene.mesh().faces.size());
    wait_for_shutdown_signal(duration_s);
    runtime.stop();
    spdlog::info(
        "summary: {} images ({} repeats answered), {} trajectories refused, {} captures "
        "refused",
        images.load(), repeats.load(), refused.load(), refused_captures.load());
  } catch (const ConfigError& e) {
    std::cerr << "ephor-stripe-sim: " << e.what() << "\n";
    return 2;
  } catch (const SceneFileError& e) {
    std::cerr << "ephor-stripe-sim: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
  return 0;
}
