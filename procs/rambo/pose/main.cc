// ephor-rambo-pose: the target's pose from each frame's image triples (RAMBO
// paper, section 5: triangle pairs, clustering, pruning after consistent
// poses; TrianglePoseEstimator), moved to the base frame with the camera's
// pose at the frame's capture time (section 6: the arm's joints from
// ARM_STATE, interpolated to the capture time, and the camera's mount on the
// tool plate). Section 5's pruning uses a prior: the predictor's motion at
// the frame's time when it is fresh, else the last pose found.
//
//   subscribes  RAMBO_FEATURES (rambo_features_t; or --features-channel), ARM_STATE (arm_state_t),
//               RAMBO_PREDICTION (rambo_prediction_t: the prior)
//   publishes   RAMBO_POSE (rambo_pose_t: with the camera's pose and the matched
//               triangles, for the page), one per features message
//   tasks       pose (triggered by RAMBO_FEATURES: always the newest)
//
// --features-channel: the features process's triples (section 4, from the
// frames) or the simulator's oracle (see rambo_features_t).

#include <atomic>
#include <cmath>
#include <condition_variable>
#include <iostream>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include "common/config/text_proto.h"
#include "common/lcm/bus.h"
#include "common/lcm/channels.h"
#include "common/log/log.h"
#include "common/rambo/rambo_cell.h"
#include "common/rambo/rambo_channels.h"
#include "common/rambo/ransac_pose_peer.h"
#include "common/rambo/tagging_planner.h"
#include "common/rambo/target_model_file.h"
#include "common/rambo/triangle_pose_estimator.h"
#include "common/runtime/process_args.h"
#include "common/runtime/task_runtime.h"
#include "common/time/clock.h"
#include "ephor/arm_state_t.hpp"
#include "ephor/rambo_features_t.hpp"
#include "ephor/rambo_pose_t.hpp"
#include "ephor/rambo_prediction_t.hpp"
#include "procs/rambo/pose/pose_task.h"

int main(int argc, char** argv) {
  using namespace ephor;
  using namespace ephor::rambo;
  block_shutdown_signals();
  CLI::App app{"ephor-rambo-pose: target pose from image triples (triangle pairs)"};
  ProcessArgs args;
  add_process_flags(app, args, "pose");
  std::string method = "exact", features_channel = rambo::channels::kFeatures;
  double duration_s = 0.0, prior_max_age_s = 1.0;
  app.add_option("--method", method, "exact (P3P per triangle pair) or paraperspective")
      ->check(CLI::IsMember({"exact", "paraperspective"}));
  app.add_option("--features-channel", features_channel,
                 "image triples from: RAMBO_FEATURES (the features process, from the frames) or "
                 "RAMBO_FEATURES_ORACLE (the simulator's projected vertices)");
  int peer_every = 0, max_behind = 5;
  app.add_option("--max-behind", max_behind,
                 "frames waiting for the pose task beyond this many are dropped, oldest first "
                 "(default 5: 1 s at 5 Hz; a replay that must give every pose back sets it high)")
      ->check(CLI::Range(1, 1000000));
  app.add_option("--peer-every", peer_every,
                 "also run the solvePnPRansac peer on every Nth frame, on its own thread at "
                 "normal priority (RAMBO_POSE_PEER; 0 = never)")
      ->check(CLI::Range(0, 100000));
  app.add_option("--prior-max-age-s", prior_max_age_s,
                 "prune with the last pose when it is at most this old, s (0 = never prune)")
      ->check(CLI::Range(0.0, 60.0));
  std::string model_path;
  app.add_option(
      "--model", model_path,
      "target model file (common/rambo/target_model.proto; default: the built-in target)");
  app.add_option("--duration", duration_s, "exit after this many seconds (0 = until signalled)");
  if (const auto exit_status = ephor::parse_flags(app, argc, argv)) return *exit_status;
  init_logging(args.name);

  try {
    const RamboCell cell = cell_from_flags(model_path, 0);
    TrianglePoseOptions options;
    options.method = method == "exact" ? TrianglePoseMethod::kExactPerspective
                                       : TrianglePoseMethod::kParaperspective;
    const TrianglePoseEstimator estimator(cell.model, cell.camera, options);
    Bus bus(args.lcm_url, args.name);
    TaskRuntime runtime(bus, {args.name, args.host, !args.no_mlock});
    std::mutex mutex;
    // Frames ready for pose and the newest one still waiting for an
    // ARM_STATE at or after its capture time (guarded by mutex; see
    // PoseFrameQueue, pose_task.h).
    PoseFrameQueue frames(max_behind);
    // The pose task's own: the last pose found (the prior), the estimate.
    FramePoser poser(cell, estimator, prior_max_age_s);
    std::atomic<int64_t> found{0}, not_found{0}, bad{0};
    std::map<std::string, int64_t> reasons;
    // The frame handed to the peer's thread (one at a time).
    struct PeerJob {
      int64_t utime = 0, frame_index = 0;
      std::string source;
      std::vector<ImageTriple> triples;
      Eigen::Isometry3d camera = Eigen::Isometry3d::Identity();  // camera in base at capture
    };
    std::mutex peer_mutex;
    std::condition_variable peer_wake;
    std::optional<PeerJob> peer_job;
    bool peer_stop = false;  // of frames without a pose (guarded by mutex)
    bus.subscribe<rambo_prediction_t>(rambo::channels::kPrediction,
                                      [&](const rambo_prediction_t& m) {
                                        const std::optional<FittedMotion> fm = prior_motion_of(m);
                                        if (!fm) return;  // the planner names bad predictions
                                        std::lock_guard<std::mutex> lock(mutex);
                                        frames.on_motion(*fm);
                                      });
    bus.subscribe<arm_state_t>(ephor::channels::kArmState, [&](const arm_state_t& m) {
      const std::optional<arm::Joints> q = joints_of(m);
      if (!q) {
        ++bad;
        return;
      }
      {
        std::lock_guard<std::mutex> lock(mutex);
        if (!frames.on_arm_state(m.utime, *q)) return;
      }
      runtime.trigger("pose");
    });
    bus.subscribe<rambo_features_t>(features_channel, [&](const rambo_features_t& m) {
      {
        std::lock_guard<std::mutex> lock(mutex);
        if (!frames.on_features(m)) return;
      }
      runtime.trigger("pose");
    });

    runtime.add_triggered("pose", std::chrono::milliseconds(150), [&] {
      std::optional<ReadyFrame> rf;
      {
        std::lock_guard<std::mutex> lock(mutex);
        rf = frames.take();
        if (!rf) return;
        if (frames.has_ready()) runtime.trigger("pose");  // one frame per job
      }
      const rambo_features_t* f = &rf->features;
      bool malformed = false;
      rambo_pose_t out =
          poser.pose(*rf, &malformed,
                     [&](const std::vector<ImageTriple>& triples, const Eigen::Isometry3d& camera) {
                       if (peer_every > 0 && f->frame_index % peer_every == 0) {
                         std::lock_guard<std::mutex> lock(peer_mutex);
                         if (!peer_job) {  // else the peer is still on an older frame: skipped
                           peer_job = PeerJob{f->utime, f->frame_index, f->source, triples, camera};
                           peer_wake.notify_one();
                         }
                       }
                     });
      if (malformed) {
        ++bad;
        spdlog::warn("RAMBO_FEATURES frame {} from {} refused: {} ({} so far)", f->frame_index,
                     f->header.sender, out.reason, bad.load());
      }
      (out.found ? found : not_found)++;
      if (!out.found) {
        std::lock_guard<std::mutex> lock(mutex);
        ++reasons[out.reason];
      }
      if (!out.found && not_found % 20 == 1)
        spdlog::warn("frame {}: no pose: {} ({} so far)", f->frame_index, out.reason,
                     not_found.load());
      bus.publish(rambo::channels::kPose, out);
    });

    // The peer (common/rambo/ransac_pose_peer.h) on its own thread, not a
    // task of the run: at ~0.6 s a frame it would miss every deadline and
    // hold a real-time CPU; its poses are compared with ours by the
    // simulator's summary.
    std::thread peer_thread;
    if (peer_every > 0) {
      peer_thread = std::thread([&] {
        const RansacPosePeer peer(cell.model, cell.camera);
        for (;;) {
          PeerJob job;
          {
            std::unique_lock<std::mutex> lock(peer_mutex);
            peer_wake.wait(lock, [&] { return peer_job.has_value() || peer_stop; });
            if (peer_stop) return;
            job = *peer_job;
          }
          rambo_pose_t out{};
          out.utime = job.utime;
          out.frame_index = job.frame_index;
          out.features_source = job.source;
          for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) out.camera_r[3 * i + j] = job.camera.linear()(i, j);
            out.camera_t_mm[i] = job.camera.translation()[i];
          }
          const int64_t cpu0 = thread_cpu_ns();
          const auto r = peer.estimate(job.triples);
          out.pose_ms = static_cast<double>(thread_cpu_ns() - cpu0) * 1e-6;
          out.found = r.has_value();
          out.reason = r ? "" : "solvePnPRansac found no consensus";
          if (r) {
            out.matches_tried = r->hypotheses;
            out.correspondences = r->inliers;
            const Eigen::Isometry3d in_base = job.camera * r->target_in_camera;
            for (int i = 0; i < 3; ++i) {
              for (int j = 0; j < 3; ++j) out.target_r[3 * i + j] = in_base.linear()(i, j);
              out.target_t_mm[i] = in_base.translation()[i];
            }
          }
          bus.publish(rambo::channels::kPosePeer, out);
          std::lock_guard<std::mutex> lock(peer_mutex);
          peer_job.reset();
        }
      });
    }
    runtime.start();
    spdlog::info("ready: {} triangle pairs, {} model triangles", method,
                 cell.model.triangles().size());
    wait_for_shutdown_signal(duration_s);
    runtime.stop();
    if (peer_thread.joinable()) {
      {
        std::lock_guard<std::mutex> lock(peer_mutex);
        peer_stop = true;
      }
      peer_wake.notify_one();
      peer_thread.join();
    }
    std::lock_guard<std::mutex> lock(mutex);
    std::string why;
    for (const auto& [reason, n] : reasons) why += fmt::format("; {}: {}", reason, n);
    spdlog::info("summary: {} poses, {} without, {} bad messages, {} frames dropped behind{}",
                 found.load(), not_found.load(), bad.load(), frames.dropped(), why);
  } catch (const ephor::ConfigError& e) {
    // A bad --model file or --diodes: one line, status 2 (issue 18).
    std::cerr << "ephor-rambo-pose: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
  return 0;
}
