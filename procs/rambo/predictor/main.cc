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

#include <atomic>
#include <cmath>
#include <deque>
#include <iostream>
#include <mutex>
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

int main(int argc, char** argv) {
  using namespace ephor;
  using namespace ephor::rambo;
  block_shutdown_signals();
  CLI::App app{"ephor-rambo-predictor: the tumbling target's motion from its poses"};
  ProcessArgs args;
  add_process_flags(app, args, "predictor");
  double window_s = 4.0, duration_s = 0.0, max_rms_px = 3.0;
  int min_samples = 5, outliers_in_row = 0;
  bool fit_valid = false;  // the predictor's fit is of the poses in the window
  int refit_after = 10;    // outlier poses in a row (2 s at 5 Hz) that restart the fit
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
    RigidBodyPosePredictor rigid(cell.principal_moments);
    PolynomialPosePredictor poly(poly_degree, poly_rotation == "zyx"
                                                  ? RotationCoordinates::kZyxAngles
                                                  : RotationCoordinates::kRotationVector);
    PosePredictor& predictor = polynomial ? static_cast<PosePredictor&>(poly) : rigid;
    if (polynomial) window_s = poly_window_s;
    Bus bus(args.lcm_url, args.name);
    TaskRuntime runtime(bus, {args.name, args.host, !args.no_mlock});
    Mailbox<rambo_pose_t> poses;
    std::deque<std::pair<int64_t, Eigen::Isometry3d>> window;
    int64_t epoch_utime = -1;
    std::atomic<int64_t> fits{0}, failures{0}, dropped{0};

    bus.subscribe<rambo_pose_t>(rambo::channels::kPose, [&](const rambo_pose_t& m) {
      poses.put(m);
      runtime.trigger("fit");
    });

    runtime.add_triggered("fit", std::chrono::milliseconds(100), [&] {
      const auto m = poses.take();
      if (!m || !m->found) return;
      Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) p.linear()(i, j) = m->target_r[3 * i + j];
        p.translation()[i] = m->target_t_mm[i];
      }
      const bool orthonormal =
          (p.linear().transpose() * p.linear() - Eigen::Matrix3d::Identity()).norm() < 1e-6;
      if (!p.matrix().allFinite() || !orthonormal || !(m->rms_reprojection_px <= max_rms_px) ||
          (!window.empty() && m->utime <= window.back().first)) {
        ++dropped;
        return;
      }
      if (epoch_utime < 0) epoch_utime = m->utime;
      // A pose far from the fitted motion is a wrong cluster (a near-symmetric
      // view): dropped, unless --refit-after in a row disagree (then the fit
      // is the one that is wrong and starts again).
      if (fit_valid && !window.empty()) {
        const PosePrediction expected =
            predictor.predict(static_cast<double>(m->utime - epoch_utime) * 1e-6);
        const bool outlier = (expected.pose.translation() - p.translation()).norm() > max_jump_mm ||
                             rotation_angle_between(expected.pose.linear(), p.linear()) >
                                 max_jump_deg * M_PI / 180.0;
        if (outlier && ++outliers_in_row < refit_after) {
          ++dropped;
          return;
        }
        if (outlier) {
          spdlog::warn("{} poses in a row off the fitted motion: fitting afresh", refit_after);
          window.clear();
          fit_valid = false;
        }
        outliers_in_row = 0;
      }
      window.emplace_back(m->utime, p);
      while (!window.empty() &&
             static_cast<double>(m->utime - window.front().first) * 1e-6 > window_s)
        window.pop_front();
      rambo_prediction_t out{};
      no_polynomial(&out);
      out.utime = wall_us();
      out.model = predictor.name();
      out.ref_utime = m->utime;
      out.samples = static_cast<int32_t>(window.size());
      if (static_cast<int>(window.size()) < min_samples) {
        out.reason = "waiting for " + std::to_string(min_samples) + " poses";
        bus.publish(rambo::channels::kPrediction, out);
        return;
      }
      std::vector<PoseSample> samples;
      for (const auto& [u, pose] : window)
        samples.push_back({static_cast<double>(u - epoch_utime) * 1e-6, pose});
      std::string why;
      if (!predictor.fit(samples, &why)) {
        ++failures;
        fit_valid = false;
        out.reason = why;
        bus.publish(rambo::channels::kPrediction, out);
        return;
      }
      ++fits;
      fit_valid = true;
      const double t_ref = samples.back().t_s;
      const PosePrediction now = predictor.predict(t_ref);
      const Eigen::Vector3d v =
          predictor.predict(t_ref + 1.0).pose.translation() - now.pose.translation();
      const Eigen::Quaterniond q(now.pose.linear());
      // The polynomial's body rates at t_ref (for the page and a reader that
      // takes the rigid-body fields): R^T R' by a central difference of 10 ms.
      Eigen::Vector3d w = Eigen::Vector3d::Zero();
      if (polynomial) {
        const Eigen::AngleAxisd d(predictor.predict(t_ref - 0.005).pose.linear().transpose() *
                                  predictor.predict(t_ref + 0.005).pose.linear());
        w = d.axis() * d.angle() / 0.01;
        polynomial_to_message(poly.motion(), t_ref, &out);
      } else {
        w = rigid.body_rates_rad_s();
        no_polynomial(&out);
      }
      out.fitted = true;
      for (int k = 0; k < 3; ++k) {
        out.position_mm[k] = now.pose.translation()[k];
        out.velocity_mm_s[k] = v[k];
        out.body_rates_rad_s[k] = w[k];
        out.principal_moments[k] = cell.principal_moments[k];
      }
      out.orientation_wxyz[0] = q.w();
      out.orientation_wxyz[1] = q.x();
      out.orientation_wxyz[2] = q.y();
      out.orientation_wxyz[3] = q.z();
      out.position_sigma_mm = now.position_sigma_mm;
      out.rotation_sigma_rad = now.rotation_sigma_rad;
      out.rms_rotation_residual_rad = polynomial ? 0.0 : rigid.rms_rotation_residual_rad();
      bus.publish(rambo::channels::kPrediction, out);
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
    spdlog::info("summary: {} fits, {} failed, {} poses dropped", fits.load(), failures.load(),
                 dropped.load());
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
