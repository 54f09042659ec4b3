// ephor-rambo-sim: RAMBO's simulated world in real time (paper 001, section 2):
// the free-floating target tumbling with constant momenta (TumblingBody) or,
// with --carrier rm501, carried by a Mitsubishi RM-501 as in the paper's lab
// (Rm501Carrier: 5 joints swinging smoothly, no constant twist), its
// diodes and indicator electronics (DiodeIndicator), the PUMA 560's servo layer
// (ArmServo, following ephor-arm's trajectories) with the laser and the camera
// on its tool plate, the camera's frames (TargetRenderer) and ground truth.
//
//   ephor-rambo-sim --seed 1 --diodes 4 --summary out.json
//   ephor-rambo-sim --seed 1 --carrier rm501
//
// Tasks: physics (2 ms: servo and indicator in 1 ms steps; ARM_SERVO every
// 4 ms), camera (1/fps: CAMERA, RAMBO_TRUTH, RAMBO_FEATURES_ORACLE), indicator (50 ms:
// RAMBO_INDICATOR). Subscribes ARM_TRAJECTORY, and RAMBO_POSE, RAMBO_PREDICTION,
// RAMBO_PLAN for the run's summary (scored against the truth it alone has).
//
// RAMBO_FEATURES_ORACLE is an ORACLE, not vision: the visible vertices' true
// projections plus --noise-px Gaussian noise, as image triples, for runs and
// tests of the later stages without the features process (section 4, which
// reads CAMERA and publishes RAMBO_FEATURES). Its `source` says "oracle".
//
// The run ends (exit 0) one second after every diode is tagged, or after
// --max-s; the summary is written then.
//
// The world, the handlers and the tasks' work on it are SimWorld
// (sim_messages.h; the fuzz target rambo_sim runs them); this file is the wiring.

#include <algorithm>
#include <atomic>
#include <cmath>
#include <fstream>
#include <iostream>
#include <mutex>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <opencv2/imgcodecs.hpp>
#include "common/arm/arm_workcell.h"
#include "common/config/repo_paths.h"
#include "common/config/text_proto.h"
#include "common/geometry/message_pose.h"
#include "common/geometry/workcell_file.h"
#include "common/lcm/bus.h"
#include "common/lcm/channels.h"
#include "common/log/json_text.h"
#include "common/log/log.h"
#include "common/rambo/image_triple.h"
#include "common/rambo/rambo_cell.h"
#include "common/rambo/rambo_channels.h"
#include "common/rambo/rm501_carrier.h"
#include "common/rambo/target_model_file.h"
#include "common/runtime/channels.h"
#include "common/runtime/process_args.h"
#include "common/runtime/task_runtime.h"
#include "common/time/clock.h"
#include "ephor/camera_frame_t.hpp"
#include "ephor/joint_state_t.hpp"
#include "ephor/rambo_features_t.hpp"
#include "ephor/rambo_indicator_t.hpp"
#include "ephor/rambo_truth_t.hpp"

#include "common/rambo/target_renderer.h"
#include "procs/rambo/sim/sim_messages.h"

namespace {

using namespace ephor;
using namespace ephor::rambo;

}  // namespace

int main(int argc, char** argv) {
  block_shutdown_signals();
  CLI::App app{"ephor-rambo-sim: tumbling target with diodes, PUMA 560 servo, laser and camera"};
  ProcessArgs args;
  add_process_flags(app, args, "sim");
  uint64_t seed = 1;
  int diodes = 4;
  double fps = 5.0, noise_px = 0.5, spin_deg_s = 2.0, drift_mm_s = 1.0, max_s = 120.0,
         duration_s = 0.0;
  std::string workcell_path = "deploy/rambo/workcell.pbtxt", summary_path, png_path;
  app.add_option("--seed", seed, "random seed: tumble axis, tilt, drift, noise (default 1)");
  std::string model_path;
  app.add_option("--diodes", diodes, "the model's first N diodes are on the target (default 4)")
      ->check(CLI::Range(1, RamboCell::kMaxDiodes));
  app.add_option(
      "--model", model_path,
      "target model file (common/rambo/target_model.proto; default: the built-in target)");
  app.add_option("--fps", fps, "camera frames per second (default 5)")
      ->check(CLI::Range(0.5, 60.0));
  app.add_option("--noise-px", noise_px, "oracle features: pixel noise sigma (default 0.5)")
      ->check(CLI::Range(0.0, 10.0));
  app.add_option("--spin-deg-s", spin_deg_s,
                 "target's initial spin rate, deg/s (default 2); with --carrier rm501 the arm's "
                 "joint rates scale by spin/2")
      ->check(CLI::Range(0.0, 90.0));
  std::string carrier = "free";
  app.add_option("--carrier", carrier,
                 "what moves the target: free (a free-floating tumble with constant momenta, as in "
                 "space) or rm501 (carried by a 5-axis Mitsubishi RM-501, as in the paper's lab; "
                 "common/rambo/rm501_carrier.h)")
      ->check(CLI::IsMember({"free", "rm501"}));
  app.add_option("--drift-mm-s", drift_mm_s, "largest drift speed of its centre, mm/s (default 1)")
      ->check(CLI::Range(0.0, 200.0));
  int rounds = 1;
  app.add_option(
         "--rounds", rounds,
         "rounds of tagging: after every diode is tagged, all are untagged again and the "
         "next round starts, until this many are done (0 = until stopped or --max-s; "
         "default 1). The summary's time_to_all_s is the first round's, its tags the last round's")
      ->check(CLI::Range(0, 1000000));
  app.add_option("--max-s", max_s, "end the run after this long, s (default 120)")
      ->check(CLI::Range(1.0, 36000.0));
  app.add_option("--workcell", workcell_path, "work cell file (common/geometry/workcell.proto)");
  app.add_option("--summary", summary_path, "write the run's JSON summary here at the end");
  app.add_option("--duration", duration_s, "exit after this many seconds (0 = until the run ends)");
  app.add_option("--write-png", png_path, "render the first frame to this PNG and exit");
  if (const auto exit_status = ephor::parse_flags(app, argc, argv)) return *exit_status;
  init_logging(args.name);

  try {
    const geometry::Workcell workcell =
        geometry::load_workcell_file(resolve_repo_path(workcell_path));
    RamboCell cell = cell_from_flags(model_path, diodes);
    if (std::abs(workcell.tool_length_mm - cell.tool_length_mm) > 1e-6)
      throw std::invalid_argument(
          fmt::format("{}: tool_length_mm {} is not the laser's {} mm (common/rambo/rambo_cell.h)",
                      workcell_path, workcell.tool_length_mm, cell.tool_length_mm));
    const TumblingMotion motion = cell.draw_motion(seed, spin_deg_s, drift_mm_s);
    SimWorld w(cell, motion, arm::make_puma(workcell).limits());
    if (carrier == "rm501") {
      try {
        w.carrier.emplace(motion.pose0, seed, spin_deg_s / 2.0);
      } catch (const std::invalid_argument& e) {
        throw ConfigError(
            fmt::format("--carrier rm501 with --spin-deg-s {}: {}", spin_deg_s, e.what()));
      }
    }
    TargetRenderer renderer(cell.model, cell.camera, 3.0, seed);
    std::mt19937 feature_rng(static_cast<std::uint32_t>(seed * 7919u + 1u));
    cv::Mat image;

    // The carrying arm's links in the camera frame (none for the free target).
    auto links_in_camera = [](const std::vector<Eigen::Vector3d>& chain,
                              const Eigen::Isometry3d& camera) {
      std::vector<RenderedLink> links;
      for (std::size_t k = 0; k + 1 < chain.size(); ++k)
        links.push_back({camera.inverse() * chain[k], camera.inverse() * chain[k + 1],
                         Rm501Carrier::kLinkRadiusMm[k]});
      return links;
    };
    if (!png_path.empty()) {
      std::vector<Eigen::Vector3d> chain;
      if (w.carrier) {
        const auto c = w.carrier->chain(0.0);
        chain.assign(c.begin(), c.end());
      }
      const Eigen::Isometry3d camera0 = w.camera_in_base(cell.start_joints);
      renderer.render(camera0.inverse() * w.target_at(0.0), image, links_in_camera(chain, camera0));
      cv::imwrite(png_path, image);
      spdlog::info("wrote {}", png_path);
      return 0;
    }

    Bus bus(args.lcm_url, args.name);
    TaskRuntime runtime(bus, {args.name, args.host, !args.no_mlock});

    bus.subscribe<joint_trajectory_t>(ephor::channels::kArmTrajectory,
                                      [&w](const joint_trajectory_t& m) { w.on_trajectory(m); });
    bus.subscribe<rambo_pose_t>(rambo::channels::kPose,
                                [&w](const rambo_pose_t& m) { w.on_pose(m); });
    bus.subscribe<rambo_pose_t>(rambo::channels::kPosePeer,
                                [&w](const rambo_pose_t& m) { w.on_pose_peer(m); });
    bus.subscribe<rambo_prediction_t>(rambo::channels::kPrediction,
                                      [&w](const rambo_prediction_t& m) { w.on_prediction(m); });
    bus.subscribe<sched_status_t>(ephor::channels::kSchedStatus,
                                  [&w](const sched_status_t& m) { w.on_sched_status(m); });
    bus.subscribe<rambo_plan_t>(rambo::channels::kPlan,
                                [&w](const rambo_plan_t& m) { w.on_plan(m); });

    w.wall0_us = wall_us();
    w.mono0_ns = mono_ns();
    auto now_s = [&w] { return static_cast<double>(mono_ns() - w.mono0_ns) * 1e-9; };

    runtime.add_periodic("physics", std::chrono::milliseconds(2), [&] {
      if (std::optional<joint_state_t> m = w.physics_tick(now_s()))
        bus.publish(ephor::channels::kArmServo, *m);
    });

    runtime.add_periodic("camera", std::chrono::nanoseconds(static_cast<int64_t>(1e9 / fps)), [&] {
      CameraShot shot = w.camera_shot(now_s());
      rambo_truth_t& truth = shot.truth;
      const Eigen::Isometry3d& target = shot.target;
      const Eigen::Isometry3d& camera = shot.camera;
      const std::vector<Eigen::Vector3d>& carrier_chain = shot.carrier_chain;
      const Eigen::Isometry3d in_camera = camera.inverse() * target;
      renderer.render(in_camera, image, links_in_camera(carrier_chain, camera));
      camera_frame_t frame;
      frame.utime = truth.utime;
      frame.frame_index = w.frames;
      frame.width = image.cols;
      frame.height = image.rows;
      frame.data.assign(image.data, image.data + image.total());
      frame.size = static_cast<int32_t>(frame.data.size());
      bus.publish(ephor::channels::kCamera, frame);
      truth.frame_index = frame.frame_index;
      geometry::set_pose(target, truth.target_r, truth.target_t_mm);
      geometry::set_pose(camera, truth.camera_r, truth.camera_t_mm);
      for (const Eigen::Vector3d& p : carrier_chain)
        truth.carrier_mm.push_back({p.x(), p.y(), p.z()});
      truth.carrier_points = static_cast<int32_t>(truth.carrier_mm.size());
      bus.publish(rambo::channels::kTruth, truth);
      // The oracle features (see the top of this file).
      rambo_features_t f;
      f.utime = truth.utime;
      f.frame_index = frame.frame_index;
      f.source = "oracle";
      f.noise_px = noise_px;
      for (const ImageTriple& t :
           synthetic_image_triples(w.cell.model, w.cell.camera, in_camera, noise_px, &feature_rng))
        f.triples_px.push_back({t.reference_px.x(), t.reference_px.y(), t.a_px.x(), t.a_px.y(),
                                t.b_px.x(), t.b_px.y()});
      f.num_triples = static_cast<int32_t>(f.triples_px.size());
      // The corners and edges the triples stand for (the page draws them).
      auto corner_of = [&f](double x, double y) {
        for (std::size_t k = 0; k < f.corners_px.size(); ++k)
          if (f.corners_px[k][0] == x && f.corners_px[k][1] == y) return static_cast<int32_t>(k);
        f.corners_px.push_back({x, y});
        return static_cast<int32_t>(f.corners_px.size() - 1);
      };
      for (const auto& t : f.triples_px) {
        const int32_t r = corner_of(t[0], t[1]);
        for (const int32_t j : {corner_of(t[2], t[3]), corner_of(t[4], t[5])}) {
          const std::vector<int32_t> e{std::min(r, j), std::max(r, j)};
          if (std::find(f.edges.begin(), f.edges.end(), e) == f.edges.end()) f.edges.push_back(e);
        }
      }
      f.num_corners = static_cast<int32_t>(f.corners_px.size());
      f.num_edges = static_cast<int32_t>(f.edges.size());
      bus.publish(rambo::channels::kFeaturesOracle, f);
      ++w.frames;
    });

    std::atomic<bool> finished{false};
    runtime.add_periodic("indicator", std::chrono::milliseconds(50), [&] {
      bool done = false;
      rambo_indicator_t m = w.indicator_tick(now_s(), rounds, max_s, done);
      if (done) finished = true;
      bus.publish(rambo::channels::kIndicator, m);
    });

    runtime.start();
    spdlog::info(
        "running: seed {}, target {}, {} diodes (acceptance {} deg, lens radius {} mm, {} s lit), "
        "spin {} deg/s, {} fps, oracle features with {} px noise",
        seed, carrier == "rm501" ? "carried by the RM-501" : "free-floating, constant momenta",
        diodes, RamboCell::kAcceptanceDeg, RamboCell::kLensRadiusMm, RamboCell::kRequiredS,
        spin_deg_s, fps, noise_px);
    const auto t_end =
        duration_s > 0 ? mono_ns() + static_cast<int64_t>(duration_s * 1e9) : INT64_MAX;
    while (!finished && mono_ns() < t_end) {
      if (wait_for_shutdown_signal(0.05) != 0) break;
    }
    runtime.stop();
    std::lock_guard<std::mutex> lock(w.mutex);
    const nlohmann::json s = w.summary(seed, spin_deg_s);
    spdlog::info("summary: {}", json_text(s));
    if (!summary_path.empty()) {
      std::ofstream out(summary_path);
      out << json_text(s, 2) << "\n";
      if (!out) spdlog::error("could not write the summary to {}", summary_path);
    }
  } catch (const ephor::ConfigError& e) {
    // A file given on the command line is bad: one line, status 2 (issue 18).
    std::cerr << "ephor-rambo-sim: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
  return 0;
}
