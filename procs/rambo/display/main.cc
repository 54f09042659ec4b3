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
//   serves      / (the page), /api/state (RamboDisplayState::state), /api/model (the
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
#include "procs/rambo/display/rambo_display_state.h"
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

namespace {

Eigen::Isometry3d pose_of(const double r[9], const double t[3]) {
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) p.linear()(i, j) = r[3 * i + j];
    p.translation()[i] = t[i];
  }
  return p;
}

bool finite(const Eigen::Isometry3d& p) { return p.matrix().allFinite(); }

}  // namespace

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
    RamboDisplayState state(rambo::cell_from_flags(model_path, diodes));
    Bus bus(args.lcm_url, args.name);
    display::DisplayServer server(bus, options, &rambo_display::find_web_asset);
    server.subscribe<rambo_features_t>(features_channel, [&](const rambo_features_t& m) {
      FeaturesView f;
      f.utime = m.utime;
      f.frame_index = m.frame_index;
      f.source = m.source;
      f.triples = m.num_triples;
      if (static_cast<int>(m.corners_px.size()) != m.num_corners ||
          static_cast<int>(m.edges.size()) != m.num_edges)
        return;  // malformed: the pose process names it
      for (const auto& c : m.corners_px)
        if (std::isfinite(c[0]) && std::isfinite(c[1])) f.corners_px.push_back({c[0], c[1]});
      for (const auto& e : m.edges)
        if (e[0] >= 0 && e[1] >= 0 && e[0] < static_cast<int>(f.corners_px.size()) &&
            e[1] < static_cast<int>(f.corners_px.size()))
          f.edges.push_back({e[0], e[1]});
      state.on_features(std::move(f));
    });
    server.subscribe<rambo_pose_t>(rambo::channels::kPose, [&](const rambo_pose_t& m) {
      PoseView p;
      p.utime = m.utime;
      p.frame_index = m.frame_index;
      p.found = m.found;
      p.reason = m.reason;
      p.target_in_base = pose_of(m.target_r, m.target_t_mm);
      p.camera_in_base = pose_of(m.camera_r, m.camera_t_mm);
      p.pose_ms = m.pose_ms;
      p.correspondences = m.correspondences;
      p.pruned = m.pruned;
      p.features_source = m.features_source;
      if (p.found && (!finite(p.target_in_base) || !finite(p.camera_in_base))) return;
      if (static_cast<int>(m.matched_triangles_px.size()) == m.num_matched_triangles)
        for (const auto& t : m.matched_triangles_px)
          p.matched_triangles_px.push_back({t[0], t[1], t[2], t[3], t[4], t[5]});
      state.on_pose(std::move(p));
    });
    server.subscribe<rambo_truth_t>(rambo::channels::kTruth, [&](const rambo_truth_t& m) {
      TruthView t;
      t.utime = m.utime;
      t.frame_index = m.frame_index;
      t.target_in_base = pose_of(m.target_r, m.target_t_mm);
      t.camera_in_base = pose_of(m.camera_r, m.camera_t_mm);
      for (const auto& p : m.carrier_mm) {
        const Eigen::Vector3d v(p.at(0), p.at(1), p.at(2));
        if (!v.allFinite()) return;
        t.carrier_mm.push_back(v);
      }
      if (finite(t.target_in_base) && finite(t.camera_in_base)) state.on_truth(t);
    });
    server.subscribe<rambo_plan_t>(rambo::channels::kPlan, [&](const rambo_plan_t& m) {
      PlanView p;
      p.order = m.order;
      p.current_task = m.current_task;
      p.status = m.status;
      p.greedy_trajectories = m.greedy_trajectories;
      p.exhaustive_trajectories = m.exhaustive_trajectories;
      p.dp_trajectories = m.dp_trajectories;
      p.order_total_s = m.order_total_s;
      p.goals_sent = m.goals_sent;
      state.on_plan(std::move(p));
    });
    server.subscribe<rambo_indicator_t>(rambo::channels::kIndicator,
                                        [&](const rambo_indicator_t& m) {
                                          IndicatorView i;
                                          i.utime = m.utime;
                                          i.lit_diode = m.lit_diode;
                                          i.lit_s = m.lit_s;
                                          i.required_s = m.required_s;
                                          i.acceptance_deg = m.acceptance_deg;
                                          i.tagged.assign(m.tagged.begin(), m.tagged.end());
                                          i.tagged_utime = m.tagged_utime;
                                          i.beam_angle_deg = m.beam_angle_deg;
                                          i.beam_offset_mm = m.beam_offset_mm;
                                          state.on_indicator(std::move(i));
                                        });
    server.subscribe<arm_state_t>(ephor::channels::kArmState, [&](const arm_state_t& m) {
      arm::Joints q;
      for (int j = 0; j < 6; ++j) q[j] = m.q[j];
      state.on_arm_joints(q);
    });
    // Heard for the debug dump and the rates only.
    server.subscribe<rambo_prediction_t>(rambo::channels::kPrediction, nullptr);
    server.set_state_builder([&](int64_t) { return state.state(); });
    server.add_json_route("/api/model", [&](int64_t) { return state.model(); });
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
