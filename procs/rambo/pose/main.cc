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
#include <deque>
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
    const arm::Puma560 arm(cell.tool_length_mm);
    Bus bus(args.lcm_url, args.name);
    TaskRuntime runtime(bus, {args.name, args.host, !args.no_mlock});
    std::mutex mutex;
    std::deque<std::pair<int64_t, arm::Joints>> joints;  // ARM_STATE history, utime -> q
    // Frames ready for pose, oldest first, and the newest one still waiting
    // for an ARM_STATE at or after its capture time (guarded by mutex): the
    // camera's pose is interpolated between the states around the capture,
    // so a frame is taken up only once the arm has reported past it; what
    // the estimate sees then does not depend on how fast messages arrived,
    // and a recorded run replays to the same poses (rambo_replay_test).
    struct ReadyFrame {
      rambo_features_t features;
      std::optional<arm::Joints> q;        // at the capture time (rad)
      std::optional<FittedMotion> motion;  // the predictor's newest fit then
    };
    std::deque<ReadyFrame> ready;
    std::optional<rambo_features_t> waiting;
    int64_t dropped = 0;  // frames not estimated: more than --max-behind behind
    std::optional<std::pair<int64_t, Eigen::Isometry3d>> last;  // newest found pose in base
    std::optional<FittedMotion> motion;                         // the predictor's newest fit
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
    bus.subscribe<rambo_prediction_t>(
        rambo::channels::kPrediction, [&](const rambo_prediction_t& m) {
          if (!m.fitted) return;
          FittedMotion fm;
          fm.t_ref_s = static_cast<double>(m.ref_utime) * 1e-6;
          fm.position_mm = Eigen::Vector3d(m.position_mm[0], m.position_mm[1], m.position_mm[2]);
          fm.velocity_mm_s =
              Eigen::Vector3d(m.velocity_mm_s[0], m.velocity_mm_s[1], m.velocity_mm_s[2]);
          fm.orientation = Eigen::Quaterniond(m.orientation_wxyz[0], m.orientation_wxyz[1],
                                              m.orientation_wxyz[2], m.orientation_wxyz[3]);
          fm.body_rates_rad_s =
              Eigen::Vector3d(m.body_rates_rad_s[0], m.body_rates_rad_s[1], m.body_rates_rad_s[2]);
          fm.principal_moments = Eigen::Vector3d(m.principal_moments[0], m.principal_moments[1],
                                                 m.principal_moments[2]);
          if (!fm.finite()) return;  // the planner names bad predictions
          fm.orientation.normalize();
          std::lock_guard<std::mutex> lock(mutex);
          motion = fm;
        });

    // The joints at utime, linear between ARM_STATE samples (caller holds mutex).
    auto joints_at = [&](int64_t utime) -> std::optional<arm::Joints> {
      if (joints.empty() || utime < joints.front().first) return std::nullopt;
      if (utime >= joints.back().first)
        return utime - joints.back().first < 50'000 ? std::optional(joints.back().second)
                                                    : std::nullopt;
      for (std::size_t k = 1; k < joints.size(); ++k) {
        if (joints[k].first < utime) continue;
        const double a = static_cast<double>(utime - joints[k - 1].first) /
                         static_cast<double>(joints[k].first - joints[k - 1].first);
        return arm::Joints((1.0 - a) * joints[k - 1].second + a * joints[k].second);
      }
      return std::nullopt;
    };

    // A frame taken up with the camera's joints and the predictor's motion
    // as they are when it becomes ready, in the order messages came (caller
    // holds mutex): what its pose then depends on does not depend on how
    // long the pose task took to get to it.
    auto make_ready = [&](rambo_features_t f) {
      ReadyFrame r;
      r.q = joints_at(f.utime);
      r.motion = motion;
      r.features = std::move(f);
      ready.push_back(std::move(r));
    };
    bus.subscribe<arm_state_t>(ephor::channels::kArmState, [&](const arm_state_t& m) {
      arm::Joints q;
      for (int j = 0; j < 6; ++j) q[j] = m.q[j];
      if (!q.allFinite()) {
        ++bad;
        return;
      }
      {
        std::lock_guard<std::mutex> lock(mutex);
        if (!joints.empty() && m.utime <= joints.back().first) return;
        joints.emplace_back(m.utime, q);
        while (joints.size() > 1000) joints.pop_front();  // 10 s at 100 Hz
        if (!waiting || m.utime < waiting->utime) return;
        make_ready(std::move(*waiting));
        waiting.reset();
      }
      runtime.trigger("pose");
    });
    bus.subscribe<rambo_features_t>(features_channel, [&](const rambo_features_t& m) {
      {
        std::lock_guard<std::mutex> lock(mutex);
        // A newer frame: the one still waiting goes as it is (its camera
        // pose from the last state, or none).
        if (waiting) make_ready(std::move(*waiting));
        waiting.reset();
        if (!joints.empty() && joints.back().first >= m.utime)
          make_ready(m);
        else
          waiting = m;
        while (ready.size() > static_cast<std::size_t>(max_behind)) {
          ready.pop_front();
          ++dropped;
        }
        if (ready.empty()) return;
      }
      runtime.trigger("pose");
    });

    runtime.add_triggered("pose", std::chrono::milliseconds(150), [&] {
      std::optional<ReadyFrame> rf;
      {
        std::lock_guard<std::mutex> lock(mutex);
        if (ready.empty()) return;
        rf = std::move(ready.front());
        ready.pop_front();
        if (!ready.empty()) runtime.trigger("pose");  // one frame per job
      }
      const rambo_features_t* f = &rf->features;
      rambo_pose_t out{};
      out.utime = f->utime;
      out.frame_index = f->frame_index;
      out.features_source = f->source;
      out.camera_r[0] = out.camera_r[4] = out.camera_r[8] = 1.0;  // unknown until the joints are
      std::vector<ImageTriple> triples;
      bool finite = static_cast<int>(f->triples_px.size()) == f->num_triples;
      for (const auto& t : f->triples_px) {
        ImageTriple it;
        it.reference_px = {t[0], t[1]};
        it.a_px = {t[2], t[3]};
        it.b_px = {t[4], t[5]};
        finite =
            finite && it.reference_px.allFinite() && it.a_px.allFinite() && it.b_px.allFinite();
        triples.push_back(it);
      }
      const std::optional<arm::Joints>& q = rf->q;
      const std::optional<FittedMotion>& motion_then = rf->motion;
      std::optional<Eigen::Isometry3d> prior_in_base;
      {
        // `last` is this task's own (frames are taken in order).
        std::lock_guard<std::mutex> lock(mutex);
        const double t_frame = static_cast<double>(f->utime) * 1e-6;
        if (motion_then && prior_max_age_s > 0 &&
            t_frame - motion_then->t_ref_s <= 5.0 * prior_max_age_s &&
            t_frame >= motion_then->t_ref_s)
          prior_in_base = motion_then->pose(t_frame);
        else if (last && prior_max_age_s > 0 &&
                 static_cast<double>(f->utime - last->first) * 1e-6 <= prior_max_age_s)
          prior_in_base = last->second;
      }
      if (!finite) {
        ++bad;
        out.reason = "features message malformed (sizes or non-finite pixels)";
        spdlog::warn("RAMBO_FEATURES frame {} from {} refused: {} ({} so far)", f->frame_index,
                     f->header.sender, out.reason, bad.load());
      } else if (!q) {
        out.reason = "no arm state at the frame's capture time (camera pose unknown)";
      } else if (triples.empty()) {
        out.reason = "no image triples in the frame";
      } else {
        const Eigen::Isometry3d camera = arm.forward(*q) * cell.camera_in_tool;
        for (int i = 0; i < 3; ++i) {
          for (int j = 0; j < 3; ++j) out.camera_r[3 * i + j] = camera.linear()(i, j);
          out.camera_t_mm[i] = camera.translation()[i];
        }
        if (peer_every > 0 && f->frame_index % peer_every == 0) {
          std::lock_guard<std::mutex> lock(peer_mutex);
          if (!peer_job) {  // else the peer is still on an older frame: skipped
            peer_job = PeerJob{f->utime, f->frame_index, f->source, triples, camera};
            peer_wake.notify_one();
          }
        }
        const Eigen::Isometry3d prior =
            prior_in_base ? camera.inverse() * *prior_in_base : Eigen::Isometry3d::Identity();
        const int64_t cpu0 = thread_cpu_ns();
        const TrianglePoseResult r = estimator.estimate(triples, prior_in_base ? &prior : nullptr);
        out.pose_ms = static_cast<double>(thread_cpu_ns() - cpu0) * 1e-6;
        out.pruned = prior_in_base.has_value();
        out.matches_tried = r.matches_tried;
        out.cluster_size = r.cluster_size;
        out.correspondences = r.correspondences;
        out.rms_reprojection_px = r.rms_reprojection_px;
        out.found = r.found;
        out.reason = r.reason;
        for (const MatchedTriangle& m : matched_triangles(cell.model, triples, r)) {
          const ImageTriple& t = triples[static_cast<std::size_t>(m.triple)];
          out.matched_triangles_px.push_back({t.reference_px.x(), t.reference_px.y(), t.a_px.x(),
                                              t.a_px.y(), t.b_px.x(), t.b_px.y()});
          out.matched_triangle_vertices.push_back(
              {m.vertices.reference, m.vertices.a, m.vertices.b});
        }
        out.num_matched_triangles = static_cast<int32_t>(out.matched_triangles_px.size());
        if (r.found) {
          const Eigen::Isometry3d in_base = camera * r.target_in_camera;
          for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) out.target_r[3 * i + j] = in_base.linear()(i, j);
            out.target_t_mm[i] = in_base.translation()[i];
          }
          std::lock_guard<std::mutex> lock(mutex);
          last = std::make_pair(f->utime, in_base);
        }
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
                 found.load(), not_found.load(), bad.load(), dropped, why);
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
