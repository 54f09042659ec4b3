// ephor-sphere-guidance: the chaser's guidance (issue 15; paper 002,
// section 1: the estimates "filtered by guidance and control software").
// Each SPHERE_ESTIMATE goes through a constant-velocity Kalman filter
// (SphereTracker, measurement sigma from the paper's accuracy at the
// distance), and the approach (ApproachController: a braking profile to
// the capture distance, the offset across the boresight driven to zero)
// gives the chaser's velocity from the window after next on.
//
//   subscribes  SPHERE_ESTIMATE (sphere_estimate_t)
//   publishes   SPHERE_GUIDANCE (sphere_guidance_t), one per estimate: the
//               commanded chaser velocity, the filtered state and its
//               sigmas, the phase
//   tasks       guide (triggered by each estimate)

#include <atomic>
#include <cmath>
#include <mutex>
#include <string>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include "common/lcm/bus.h"
#include "common/lcm/mailbox.h"
#include "common/log/log.h"
#include "common/runtime/process_args.h"
#include "common/runtime/task_runtime.h"
#include "common/sphere/guidance/sphere_guidance.h"
#include "common/sphere/sphere_channels.h"
#include "common/time/clock.h"
#include "ephor/sphere_estimate_t.hpp"
#include "ephor/sphere_guidance_t.hpp"
#include "procs/sphere/guidance/guidance_messages.h"

namespace {

using namespace ephor;
using namespace ephor::sphere;

}  // namespace

int main(int argc, char** argv) {
  block_shutdown_signals();
  CLI::App app{"ephor-sphere-guidance: Kalman filter of the sphere and the chaser's approach"};
  ProcessArgs args;
  add_process_flags(app, args, "guidance");
  GuidanceConfig config;
  double duration_s = 0.0;
  app.add_option("--window-s", config.approach.window_s,
                 "the ranger's window: commands take effect at its boundaries (default 0.5)")
      ->check(CLI::Range(0.05, 10.0));
  app.add_option("--accel-m-s2", config.approach.max_accel_m_s2,
                 "the chaser's acceleration limit (default 0.05 m/s^2, as the ranger's)")
      ->check(CLI::Range(1e-4, 10.0));
  app.add_option("--capture-m", config.approach.capture_distance_m,
                 "capture distance along the boresight (default 1 m)")
      ->check(CLI::Range(0.2, 100.0));
  app.add_option("--final-speed-m-s", config.approach.final_speed_m_s,
                 "closing speed over the last part (default 0.01; capture needs < 0.02)")
      ->check(CLI::Range(1e-4, 1.0));
  app.add_option("--braking-m-s2", config.approach.braking_accel_m_s2,
                 "deceleration of the braking profile (default 0.02)")
      ->check(CLI::Range(1e-4, 10.0));
  app.add_option("--max-closing-m-s", config.approach.max_closing_m_s,
                 "fastest closing speed (default 0.5)")
      ->check(CLI::Range(1e-3, 10.0));
  app.add_option("--measurement-sigma-m", config.measurement_sigma_m,
                 "sigma of each estimate per axis (m; default 0 = the paper's 8 mm)")
      ->check(CLI::Range(0.0, 10.0));
  app.add_option("--min-updates", config.min_updates,
                 "estimates in the track before the chaser moves (default 3)")
      ->check(CLI::Range(1, 1000));
  app.add_option("--duration", duration_s, "exit after this many seconds (0 = until signalled)")
      ->check(CLI::Range(0.0, 1e7));
  if (const auto exit_status = ephor::parse_flags(app, argc, argv)) return *exit_status;
  init_logging(args.name);

  try {
    SphereGuidance guidance(config);
    Bus bus(args.lcm_url, args.name);
    TaskRuntime runtime(bus, {args.name, args.host, !args.no_mlock});
    Mailbox<sphere_estimate_t> estimates;
    std::atomic<int64_t> published{0};
    ApproachPhase last_phase = ApproachPhase::kAcquire;
    bool logged_tracking = false;

    bus.subscribe<sphere_estimate_t>(channels::kEstimate, [&](const sphere_estimate_t& m) {
      estimates.put(m);
      runtime.trigger("guide");
    });

    runtime.add_triggered("guide", std::chrono::milliseconds(20), [&] {
      const auto m = estimates.take();
      if (!m) return;
      const int restarts_before = guidance.restarts();
      const auto out = guidance.on_estimate(estimate_input_of(*m));
      if (guidance.restarts() != restarts_before) {
        spdlog::info("window {} after a later one: the ranger started again; new track", m->window);
      }
      if (!out) {
        if (guidance.bad_inputs() <= 10 || guidance.bad_inputs() % 100 == 0) {
          spdlog::warn(
              "SPHERE_ESTIMATE window {} from {} ignored: not newer or not finite ({} so far)",
              m->window, m->header.sender, guidance.bad_inputs());
        }
        return;
      }
      sphere_guidance_t g = guidance_message_of(*out, guidance, config);
      g.utime = wall_us();
      bus.publish(channels::kGuidance, g);
      ++published;
      if (out->tracking && !logged_tracking) {
        logged_tracking = true;
        spdlog::info(
            "tracking: sphere at ({:.3f}, {:.3f}, {:.3f}) m, moving ({:.3f}, {:.3f}, {:.3f}) m/s",
            out->state.position_m.x(), out->state.position_m.y(), out->state.position_m.z(),
            out->state.velocity_m_s.x(), out->state.velocity_m_s.y(), out->state.velocity_m_s.z());
      }
      if (out->command.phase != last_phase) {
        last_phase = out->command.phase;
        spdlog::info("{}: {:.2f} m to the capture point, closing at {:.3f} m/s, offset {:.3f} m",
                     to_string(last_phase), g.range_to_capture_m, -out->state.velocity_m_s.z(),
                     out->state.position_m.head<2>().norm());
      }
      if (out->update == SphereTracker::Update::kRejected) {
        spdlog::info("window {}: estimate refused by the filter's gate ({} so far)", m->window,
                     guidance.estimates_rejected());
      } else if (out->update == SphereTracker::Update::kReinitialised) {
        spdlog::info("window {}: a new sphere: the filter starts again", m->window);
      }
    });

    runtime.start();
    spdlog::info("ready: waiting for SPHERE_ESTIMATE");
    wait_for_shutdown_signal(duration_s);
    runtime.stop();
    spdlog::info(
        "summary: {} commands, {} estimates used ({} down-weighted), {} refused by the gate, {} "
        "windows without an estimate, {} bad messages, {} estimates overwritten before use",
        published.load(), guidance.estimates_used(), guidance.estimates_downweighted(),
        guidance.estimates_rejected(), guidance.no_estimates(), guidance.bad_inputs(),
        estimates.overwritten());
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
  return 0;
}
