// ephor-rambo-predictor: the target's motion from its recent poses (RAMBO
// paper, section 6, and beyond it: a torque-free rigid body with constant
// momenta, RigidBodyPosePredictor, fitted to the last --window-s of poses).
// Publishes the fitted state, from which any later pose follows.
//
// The model follows what moves the target (--carrier, from the manifest): a
// free-floating tumble is a rigid body with constant momenta; a target
// carried by the RM-501 is not (its joints swing it), so it gets the paper's
// polynomial fits of the six pose coordinates (PolynomialPosePredictor:
// --poly-degree over --poly-window-s, the rotation as the paper's three
// angles or a rotation vector), whose coefficients the message carries.
// --motion-model overrides the choice. The defaults (quadratic in the ZYX
// angles over 4 s) are the best of ephor-bench-rambo --sections
// live-prediction for the RM-501's motion at 0.5-2 s.
//
//   subscribes  RAMBO_POSE (rambo_pose_t)
//   publishes   RAMBO_PREDICTION (rambo_prediction_t), after every usable pose
//   tasks       fit (triggered by RAMBO_POSE)
//
// Times inside are seconds since the first pose (a fit in absolute epoch
// seconds would lose precision); messages carry absolute utimes.

#include <iostream>
#include <mutex>
#include <optional>
#include <string>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include "common/config/text_proto.h"
#include "common/lcm/bus.h"
#include "common/lcm/mailbox.h"
#include "common/log/log.h"
#include "common/rambo/polynomial_pose_predictor.h"
#include "common/rambo/prediction_message.h"
#include "common/rambo/rambo_cell.h"
#include "common/rambo/rambo_channels.h"
#include "common/rambo/rigid_body_pose_predictor.h"
#include "common/rambo/target_model_file.h"
#include "common/runtime/process_args.h"
#include "common/runtime/task_runtime.h"
#include "common/time/clock.h"
#include "ephor/rambo_pose_t.hpp"
#include "ephor/rambo_prediction_t.hpp"
#include "procs/rambo/predictor/predictor_task.h"

int main(int argc, char** argv) {
  using namespace ephor;
  using namespace ephor::rambo;
  block_shutdown_signals();
  CLI::App app{"ephor-rambo-predictor: the tumbling target's motion from its poses"};
  ProcessArgs args;
  add_process_flags(app, args, "predictor");
  double window_s = 4.0, duration_s = 0.0, max_rms_px = 3.0;
  int min_samples = 5;
  int refit_after = 10;  // outlier poses in a row (2 s at 5 Hz) that restart the fit
  double max_jump_mm = 40.0, max_jump_deg = 15.0;
  app.add_option("--window-s", window_s, "fit the poses of this last span, s (default 4)")
      ->check(CLI::Range(0.5, 120.0));
  app.add_option("--min-samples", min_samples, "poses needed for a fit (default 5)")
      ->check(CLI::Range(3, 1000));
  app.add_option("--max-rms-px", max_rms_px, "drop poses with more reprojection error, px")
      ->check(CLI::Range(0.1, 100.0));
  app.add_option("--refit-after", refit_after, "outlier poses in a row that restart the fit (10)")
      ->check(CLI::Range(1, 1000));
  app.add_option("--max-jump-mm", max_jump_mm, "drop a pose this far from the fit, mm (40)");
  app.add_option("--max-jump-deg", max_jump_deg, "or turned this far from it, deg (15)");
  std::string carrier = "free", motion_model = "auto";
  int poly_degree = 2;
  double poly_window_s = 4.0;
  std::string poly_rotation = "zyx";
  app.add_option("--carrier", carrier,
                 "what moves the target: free (a rigid-body fit) or rm501 (the polynomial fits)")
      ->check(CLI::IsMember({"free", "rm501"}));
  app.add_option("--motion-model", motion_model,
                 "auto (by --carrier), rigid-body or polynomial (default auto)")
      ->check(CLI::IsMember({"auto", "rigid-body", "polynomial"}));
  app.add_option("--poly-degree", poly_degree, "degree of the polynomial fits (default 2)")
      ->check(CLI::Range(0, 5));
  app.add_option("--poly-window-s", poly_window_s,
                 "the polynomial fits' window, s (default 4; the rigid body's is --window-s)")
      ->check(CLI::Range(0.5, 120.0));
  app.add_option("--poly-rotation", poly_rotation,
                 "the rotation's three coordinates: zyx (the paper's yaw, pitch, roll; default) or "
                 "rotation-vector")
      ->check(CLI::IsMember({"zyx", "rotation-vector"}));
  std::string model_path;
  app.add_option(
      "--model", model_path,
      "target model file (common/rambo/target_model.proto; default: the built-in target)");
  app.add_option("--duration", duration_s, "exit after this many seconds (0 = until signalled)");
  if (const auto exit_status = ephor::parse_flags(app, argc, argv)) return *exit_status;
  init_logging(args.name);

  try {
    const RamboCell cell = cell_from_flags(model_path, 0);
    const bool polynomial =
        motion_model == "polynomial" || (motion_model == "auto" && carrier == "rm501");
    if (polynomial) window_s = poly_window_s;
    PoseFitterOptions fit_options;
    fit_options.polynomial = polynomial;
    fit_options.window_s = window_s;
    fit_options.min_samples = min_samples;
    fit_options.max_rms_px = max_rms_px;
    fit_options.refit_after = refit_after;
    fit_options.max_jump_mm = max_jump_mm;
    fit_options.max_jump_deg = max_jump_deg;
    fit_options.poly_degree = poly_degree;
    fit_options.poly_rotation = poly_rotation == "zyx" ? RotationCoordinates::kZyxAngles
                                                       : RotationCoordinates::kRotationVector;
    fit_options.principal_moments = cell.principal_moments;
    PoseFitter fitter(fit_options);  // the fit task's own
    Bus bus(args.lcm_url, args.name);
    TaskRuntime runtime(bus, {args.name, args.host, !args.no_mlock});
    Mailbox<rambo_pose_t> poses;

    bus.subscribe<rambo_pose_t>(rambo::channels::kPose, [&](const rambo_pose_t& m) {
      poses.put(m);
      runtime.trigger("fit");
    });

    runtime.add_triggered("fit", std::chrono::milliseconds(100), [&] {
      const auto m = poses.take();
      if (!m) return;
      std::optional<rambo_prediction_t> out = fitter.on_pose(*m, wall_us());
      if (out) bus.publish(rambo::channels::kPrediction, *out);
    });

    runtime.start();
    if (polynomial)
      spdlog::info(
          "ready: polynomial fits (degree {}, rotation as {}) over {} s, at least {} poses",
          poly_degree, poly_rotation, window_s, min_samples);
    else
      spdlog::info("ready: rigid-body fit over {} s, at least {} poses", window_s, min_samples);
    wait_for_shutdown_signal(duration_s);
    runtime.stop();
    spdlog::info("summary: {} fits, {} failed, {} poses dropped", fitter.fits(), fitter.failures(),
                 fitter.dropped());
  } catch (const ephor::ConfigError& e) {
    // A bad --model file or --diodes: one line, status 2 (issue 18).
    std::cerr << "ephor-rambo-predictor: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
  return 0;
}
