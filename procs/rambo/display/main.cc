// ephor-rambo-display: the RAMBO system's live page (paper 001; issue 17 item
// 6) on the shared DisplayServer (common/display): the camera image with the
// corners and edges found, the image triangles the pose matched and the
// model's outline by the estimated pose; the target's estimated and true
// poses, the camera and the laser's beam in a 3-D view (three.js, served by
// every display from Debian's libjs-three at /lib/three.min.js); the planned
// order of the diodes and which are tagged; a STOP button for the arm.
//
//   ephor-rambo-display [--http-address 127.0.0.1] [--http-port 8083] [--model F] [--diodes N]
//
//   subscribes  CAMERA (for /api/frame.jpg), RAMBO_FEATURES (or --features-channel),
//               RAMBO_POSE, RAMBO_TRUTH, RAMBO_PLAN, RAMBO_INDICATOR, ARM_STATE,
//               RAMBO_PREDICTION (debug dump only), EPHOR_SCHED_STATUS
//   serves      / (the page), /api/state (RamboDisplayFeed::state), /api/model (the
//               target's vertices, faces and diodes), /api/frame.jpg, /api/debug

#include <iostream>
#include <string>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include "common/config/text_proto.h"
#include "common/display/display_server.h"
#include "common/display/lcm_json.h"
#include "common/lcm/bus.h"
#include "common/lcm/channels.h"
#include "common/log/log.h"
#include "common/rambo/rambo_channels.h"
#include "common/rambo/target_model_file.h"
#include "common/runtime/process_args.h"
#include "ephor/arm_state_t.hpp"
#include "ephor/rambo_features_t.hpp"
#include "ephor/rambo_indicator_t.hpp"
#include "ephor/rambo_plan_t.hpp"
#include "ephor/rambo_pose_t.hpp"
#include "ephor/rambo_prediction_t.hpp"
#include "ephor/rambo_truth_t.hpp"
#include "procs/rambo/display/rambo_display_feed.h"
#include "procs/rambo/display/rambo_web_assets.h"

namespace ephor {
// For the debug dump (GET /api/debug).
EPHOR_TO_JSON(rambo_features_t, utime, header, frame_index, source, noise_px, num_triples,
              triples_px, num_corners, corners_px, num_edges, edges)
EPHOR_TO_JSON(rambo_pose_t, utime, header, frame_index, found, reason, target_r, target_t_mm,
              pose_ms, matches_tried, cluster_size, correspondences, rms_reprojection_px, pruned,
              features_source, camera_r, camera_t_mm, num_matched_triangles, matched_triangles_px,
              matched_triangle_vertices)
EPHOR_TO_JSON(rambo_truth_t, utime, header, frame_index, target_r, target_t_mm, camera_r,
              camera_t_mm, body_rates_rad_s, carrier_points, carrier_mm)
EPHOR_TO_JSON(rambo_plan_t, utime, header, num_tasks, order, current_task, status,
              greedy_trajectories, exhaustive_trajectories, dp_trajectories, order_total_s,
              goals_sent)
EPHOR_TO_JSON(rambo_indicator_t, utime, header, num_diodes, lit_diode, lit_s, tagged, tagged_utime,
              tagged_count, acceptance_deg, lens_radius_mm, required_s, beam_angle_deg,
              beam_offset_mm)
EPHOR_TO_JSON(rambo_prediction_t, utime, header, fitted, reason, model, ref_utime, samples,
              position_mm, velocity_mm_s, orientation_wxyz, body_rates_rad_s, principal_moments,
              position_sigma_mm, rotation_sigma_rad, rms_rotation_residual_rad, poly_terms,
              poly_rotation, poly_t_mid_s, poly_t_scale_s, poly_r_mid_wxyz, poly_coeff)
}  // namespace ephor

int main(int argc, char** argv) {
  using namespace ephor;
  using namespace ephor::rambo_display;
  block_shutdown_signals();
  CLI::App app{"ephor-rambo-display: live web page of the RAMBO system"};
  ProcessArgs args;
  add_process_flags(app, args, "display");
  display::DisplayServerOptions options;
  options.http_port = 8083;
  options.camera_channel = ephor::channels::kCamera;
  options.estop = true;
  std::string model_path, features_channel = rambo::channels::kFeatures;
  int diodes = 0;
  app.add_option("--http-address", options.http_address,
                 "address to serve the page on (default loopback)");
  app.add_option("--http-port", options.http_port, "TCP port of the page (default 8083)")
      ->check(CLI::Range(1, 65535));
  app.add_option(
      "--model", model_path,
      "target model file (common/rambo/target_model.proto; default: the built-in target)");
  app.add_option("--diodes", diodes, "the model's first N diodes are on the target (0 = all)")
      ->check(CLI::Range(0, rambo::RamboCell::kMaxDiodes));
  app.add_option("--features-channel", features_channel,
                 "corners and edges drawn from: RAMBO_FEATURES (the features process) or "
                 "RAMBO_FEATURES_ORACLE (the simulator's)");
  if (const auto exit_status = ephor::parse_flags(app, argc, argv)) return *exit_status;
  init_logging(args.name);
  try {
    RamboDisplayFeed feed(rambo::cell_from_flags(model_path, diodes));
    Bus bus(args.lcm_url, args.name);
    display::DisplayServer server(bus, options, &rambo_display::find_web_asset);
    server.subscribe<rambo_features_t>(features_channel,
                                       [&](const rambo_features_t& m) { feed.on_features(m); });
    server.subscribe<rambo_pose_t>(rambo::channels::kPose,
                                   [&](const rambo_pose_t& m) { feed.on_pose(m); });
    server.subscribe<rambo_truth_t>(rambo::channels::kTruth,
                                    [&](const rambo_truth_t& m) { feed.on_truth(m); });
    server.subscribe<rambo_plan_t>(rambo::channels::kPlan,
                                   [&](const rambo_plan_t& m) { feed.on_plan(m); });
    server.subscribe<rambo_indicator_t>(rambo::channels::kIndicator,
                                        [&](const rambo_indicator_t& m) { feed.on_indicator(m); });
    server.subscribe<arm_state_t>(ephor::channels::kArmState,
                                  [&](const arm_state_t& m) { feed.on_arm_state(m); });
    // Heard for the debug dump and the rates only.
    server.subscribe<rambo_prediction_t>(rambo::channels::kPrediction, nullptr);
    server.set_state_builder([&](int64_t) { return feed.state(); });
    server.add_json_route("/api/model", [&](int64_t) { return feed.model(); });
    server.run("rambo display");
  } catch (const ephor::ConfigError& e) {
    // A bad --model file or --diodes: one line, status 2.
    std::cerr << "ephor-rambo-display: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
  return 0;
}
