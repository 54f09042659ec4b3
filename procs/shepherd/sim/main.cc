// ephor-sim: the simulated work cell in real time - sheep on the field, the
// PUMA 560's servo layer and the overhead camera (common/shepherd/sim/simulator.h).
//
//   ephor-sim --sheep 4 --seed 1 --fps 30
//
// Tasks (scheduled by ephor-scheduler through the TaskRuntime):
//   physics  every 4 ms: advances the simulation to the monotonic clock
//   camera   every 1/fps: renders CAMERA (camera_frame_t) and GROUND_TRUTH
//            (shepherd_ground_truth_t, same utime and frame_index)
//   servo    every 4 ms: applies the newest ARM_TRAJECTORY, publishes
//            ARM_SERVO (joint_state_t) at 250 Hz
// Subscribes ARM_TRAJECTORY (joint_trajectory_t; malformed ones are logged,
// counted and ignored), SIM_CMD (shepherd_sim_cmd_t: herd size; reset with a seed
// on the rising edge of `reset` or a new seed while it is set) and
// SIM_TOOL_LIGHT (shepherd_tool_light_t: the calibration light on the tool tip, drawn
// in every frame while on; used by ephor-calibrate).
//
// Time: simulated time runs with CLOCK_MONOTONIC from start-up; a message's
// utime is the wall clock at start plus the simulated time of the state it
// carries, so a frame's utime is its capture time.

#include <atomic>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include "common/arm/servo_messages.h"
#include "common/config/text_proto.h"
#include "common/geometry/workcell_file.h"
#include "common/lcm/bus.h"
#include "common/lcm/channels.h"
#include "common/log/log.h"
#include "common/runtime/process_args.h"
#include "common/runtime/task_runtime.h"
#include "common/shepherd/sim/simulator.h"
#include "common/time/clock.h"
#include "ephor/camera_frame_t.hpp"
#include "ephor/joint_state_t.hpp"
#include "ephor/joint_trajectory_t.hpp"
#include "ephor/shepherd_ground_truth_t.hpp"
#include "ephor/shepherd_sim_cmd_t.hpp"
#include "ephor/shepherd_tool_light_t.hpp"
#include "procs/shepherd/sim/sim_config.h"
#include "procs/shepherd/sim/sim_messages.h"

namespace {

using ephor::sim::JointTrajectory;

void write_pgm(const std::string& path, const std::vector<uint8_t>& img, int w, int h) {
  std::ofstream out(path, std::ios::binary);
  out << "P5\n" << w << " " << h << "\n255\n";
  out.write(reinterpret_cast<const char*>(img.data()), static_cast<std::streamsize>(img.size()));
  if (!out) throw std::runtime_error("cannot write " + path);
}

// Everything the three tasks and the bus callbacks share, behind one mutex.
struct SimProcess {
  std::mutex mutex;
  ephor::sim::Simulator sim;
  double clock_s = 0.0;  // simulated time since start-up (not reset by SIM_CMD), s
  int64_t wall0_us = 0;
  int64_t mono0_ns = 0;
  std::optional<JointTrajectory> pending;  // newest valid trajectory not yet applied
  ephor::sim::SimInputs inputs;            // the bus handlers (SIM_CMD's under mutex)
  // Counters (tasks write, exit summary reads).
  std::atomic<int64_t> physics_skips{0}, frames{0};

  explicit SimProcess(ephor::sim::SimulatorConfig c) : sim(std::move(c)) {}
  int64_t utime_of(double t_s) const { return wall0_us + std::llround(t_s * 1e6); }
};

}  // namespace

int main(int argc, char** argv) {
  ephor::block_shutdown_signals();
  CLI::App app{"ephor-sim: simulated field, sheep, PUMA 560 servo layer and overhead camera"};
  ephor::ProcessArgs args;
  ephor::add_process_flags(app, args, "sim");
  int sheep = 4;
  uint64_t seed = 1;
  double fps = 30.0, speed = 8.0, noise = 2.5, reentry = 5.0, duration_s = 0.0;
  std::string config_path, pgm_path;
  app.add_option("--sheep", sheep, "sheep on the field (default 4)")->check(CLI::Range(0, 64));
  app.add_option("--seed", seed, "random seed of the world and camera noise (default 1)");
  app.add_option("--fps", fps, "camera frames per second (default 30)")
      ->check(CLI::Range(0.1, 1000.0));
  app.add_option("--speed-mm-s,--sheep-speed", speed,
                 "nominal sheep speed, mm/s (default 8, the paper's; 30 is a stress setting)")
      ->check(CLI::Range(0.0, 1000.0));
  app.add_option("--noise", noise, "camera pixel noise sigma, grey levels (default 2.5)")
      ->check(CLI::Range(0.0, 50.0));
  app.add_option("--reentry-s", reentry, "delay before an escaped sheep re-enters, s; < 0 = never");
  int clouds = 0;
  bool no_sheep_collisions = false, no_pedestal = false, no_arm_in_image = false;
  double wander = -1.0;
  app.add_option("--clouds", clouds,
                 "soft-edged clouds drifting between the camera and the field, half darker and "
                 "half brighter than it (paper 003, section 6; default 0)")
      ->check(CLI::Range(0, 32));
  app.add_flag("--no-sheep-collisions", no_sheep_collisions,
               "sheep pass through each other (to measure what collisions cost)");
  app.add_flag("--no-pedestal", no_pedestal,
               "sheep pass through the arm's pedestal (to measure what it costs)");
  app.add_flag("--no-arm-in-image", no_arm_in_image,
               "the camera does not see the arm, so it never hides a mark (to measure what the "
               "occlusion costs the tracking)");
  app.add_option("--wander-rad-s", wander,
                 "standard deviation of the sheep's heading rate, rad/s (default 0.02; 0 = "
                 "straight lines, as the planners' stand-in)")
      ->check(CLI::Range(0.0, 10.0));
  std::string workcell_path;
  app.add_option("--workcell", workcell_path,
                 "work cell file (common/geometry/workcell.proto): field, planes, arm mounting; "
                 "default: the shepherding field");
  app.add_option("--config", config_path,
                 "text config (procs/shepherd/sim/sim_config.proto); flags override it");
  app.add_option("--duration", duration_s, "exit after this many seconds (0 = until signalled)");
  app.add_option("--write-pgm", pgm_path, "render the first frame to this PGM file and exit");
  if (const auto exit_status = ephor::parse_flags(app, argc, argv)) return *exit_status;
  ephor::init_logging(args.name);

  try {
    ephor::sim::SimulatorConfig config;
    config.camera.noise_sigma = noise;
    if (!config_path.empty()) ephor::sim::apply_config_file(config_path, config, fps);
    if (app.count("--sheep") || config_path.empty()) config.world.sheep = sheep;
    if (app.count("--seed") || config_path.empty()) config.world.seed = seed;
    if (app.count("--speed-mm-s") || config_path.empty()) config.world.speed_mm_s = speed;
    if (app.count("--noise") || config_path.empty()) config.camera.noise_sigma = noise;
    if (app.count("--reentry-s") || config_path.empty()) config.world.reentry_s = reentry;
    if (!std::isfinite(config.world.reentry_s))
      throw std::invalid_argument("--reentry-s must be finite");
    config.camera.seed = config.world.seed;
    config.clouds.seed = config.world.seed;
    if (app.count("--clouds")) config.clouds.clouds = clouds;
    if (no_sheep_collisions) config.world.sheep_collisions = false;
    if (no_pedestal) config.world.pedestal = false;
    if (no_arm_in_image) config.arm_in_image = false;
    if (wander >= 0.0) config.world.wander_rad_s = wander;
    if (!workcell_path.empty()) {
      config.world.workcell = ephor::geometry::workcell_from_flag(workcell_path);
      spdlog::info("work cell {}", workcell_path);
    }

    SimProcess p(config);
    ephor::sim::CameraRenderer camera(config.camera, config.world);  // the camera task's own
    if (!pgm_path.empty()) {
      std::vector<uint8_t> img;
      ephor::sim::Simulator::render(p.sim.scene(), camera, img);
      write_pgm(pgm_path, img, camera.width(), camera.height());
      spdlog::info("wrote {}", pgm_path);
      return 0;
    }

    // Declared before the runtime so that they outlive its task threads.
    ephor::camera_frame_t frame;
    frame.width = camera.width();
    frame.height = camera.height();
    ephor::Bus bus(args.lcm_url, args.name);
    ephor::TaskRuntime runtime(bus, {args.name, args.host, !args.no_mlock});

    bus.subscribe<ephor::joint_trajectory_t>(ephor::channels::kArmTrajectory,
                                             [&p](const ephor::joint_trajectory_t& m) {
                                               auto t = p.inputs.on_trajectory(m);
                                               if (!t) return;
                                               std::lock_guard<std::mutex> lock(p.mutex);
                                               p.pending = std::move(*t);
                                             });
    bus.subscribe<ephor::shepherd_sim_cmd_t>(ephor::channels::kSimCmd,
                                             [&p](const ephor::shepherd_sim_cmd_t& m) {
                                               std::lock_guard<std::mutex> lock(p.mutex);
                                               p.inputs.on_command(m, p.sim);
                                             });

    bus.subscribe<ephor::shepherd_tool_light_t>(ephor::channels::kSimToolLight,
                                                [&p](const ephor::shepherd_tool_light_t& m) {
                                                  std::lock_guard<std::mutex> lock(p.mutex);
                                                  p.inputs.on_tool_light(m, p.sim);
                                                });

    p.wall0_us = ephor::wall_us();
    p.mono0_ns = ephor::mono_ns();

    // Steps the world up to the present (caller holds p.mutex).
    auto advance_to_now = [&p] {
      const double now_s = static_cast<double>(ephor::mono_ns() - p.mono0_ns) * 1e-9;
      if (ephor::sim::advance_to(p.sim, p.clock_s, now_s)) ++p.physics_skips;
    };
    runtime.add_periodic("physics", std::chrono::milliseconds(4), [&p, &advance_to_now] {
      std::lock_guard<std::mutex> lock(p.mutex);
      advance_to_now();
    });

    runtime.add_periodic("camera", std::chrono::nanoseconds(static_cast<int64_t>(1e9 / fps)),
                         [&p, &bus, &camera, &frame, &advance_to_now] {
                           ephor::sim::Scene scene;
                           int64_t utime = 0;
                           {
                             std::lock_guard<std::mutex> lock(p.mutex);
                             // Expose the world as it is now, not as of the
                             // last physics job (up to 4 ms old).
                             advance_to_now();
                             scene = p.sim.scene();
                             utime = p.utime_of(p.clock_s);
                           }
                           const auto gt = ephor::sim::Simulator::render(scene, camera, frame.data);
                           frame.utime = utime;
                           frame.frame_index = p.frames;
                           frame.size = static_cast<int32_t>(frame.data.size());
                           bus.publish(ephor::channels::kCamera, frame);
                           auto truth =
                               ephor::sim::ground_truth_message_of(gt, utime, frame.frame_index);
                           bus.publish(ephor::channels::kGroundTruth, truth);
                           ++p.frames;
                         });

    runtime.add_periodic("servo", std::chrono::milliseconds(4), [&p, &bus] {
      ephor::joint_state_t m;
      {
        std::lock_guard<std::mutex> lock(p.mutex);
        if (p.pending) {
          p.sim.follow(*p.pending);
          p.pending.reset();
        }
        m = ephor::sim::to_joint_state(p.sim.servo(), p.utime_of(p.clock_s));
      }
      bus.publish(ephor::channels::kArmServo, m);
    });

    runtime.start();
    spdlog::info("running: {} sheep, seed {}, {} fps, sheep speed {} mm/s", config.world.sheep,
                 config.world.seed, fps, config.world.speed_mm_s);
    spdlog::info(
        "world: {} cloud(s), sheep collisions {}, pedestal {}, arm in image {}, wander {} rad/s",
        config.clouds.clouds, config.world.sheep_collisions ? "on" : "off",
        config.world.pedestal ? "on" : "off", config.arm_in_image ? "yes" : "no",
        config.world.wander_rad_s);
    ephor::wait_for_shutdown_signal(duration_s);
    runtime.stop();
    std::lock_guard<std::mutex> lock(p.mutex);
    spdlog::info(
        "summary: escapes {} saves {} over {:.1f} s sim time, {} sheep on the field, {} frames, "
        "{} trajectories ({} ignored), {} commands ignored, {} physics skips",
        p.sim.world().escapes(), p.sim.world().saves(), p.sim.world().time_s(),
        p.sim.world().sheep().size(), p.frames.load(), p.inputs.trajectories_received(),
        p.inputs.trajectories_refused(), p.inputs.commands_refused(), p.physics_skips.load());
  } catch (const ephor::ConfigError& e) {
    // A file given on the command line is bad: one line, status 2 (issue 18).
    std::cerr << "ephor-sim: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
  return 0;
}
