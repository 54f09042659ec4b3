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

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <deque>
#include <fstream>
#include <iostream>
#include <map>
#include <mutex>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <opencv2/imgcodecs.hpp>
#include "common/arm/arm_servo.h"
#include "common/arm/arm_workcell.h"
#include "common/arm/servo_messages.h"
#include "common/config/repo_paths.h"
#include "common/config/text_proto.h"
#include "common/geometry/message_pose.h"
#include "common/geometry/workcell_file.h"
#include "common/lcm/bus.h"
#include "common/lcm/channels.h"
#include "common/log/log.h"
#include "common/rambo/diode_indicator.h"
#include "common/rambo/image_triple.h"
#include "common/rambo/pose_predictor.h"
#include "common/rambo/prediction_message.h"
#include "common/rambo/rambo_cell.h"
#include "common/rambo/rambo_channels.h"
#include "common/rambo/rm501_carrier.h"
#include "common/rambo/tagging_planner.h"
#include "common/rambo/target_model_file.h"
#include "common/rambo/tumbling_body.h"
#include "common/runtime/channels.h"
#include "common/runtime/process_args.h"
#include "common/runtime/task_runtime.h"
#include "common/time/clock.h"
#include "ephor/camera_frame_t.hpp"
#include "ephor/joint_state_t.hpp"
#include "ephor/joint_trajectory_t.hpp"
#include "ephor/rambo_features_t.hpp"
#include "ephor/rambo_indicator_t.hpp"
#include "ephor/rambo_plan_t.hpp"
#include "ephor/rambo_pose_t.hpp"
#include "ephor/rambo_prediction_t.hpp"
#include "ephor/rambo_truth_t.hpp"
#include "ephor/sched_status_t.hpp"

#include "common/rambo/target_renderer.h"

namespace {

using namespace ephor;
using namespace ephor::rambo;

constexpr double kStepS = 0.001;
constexpr double kMaxLagS = 0.5;
const double kHorizonsS[] = {0.5, 1.0, 2.0};

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  const auto k = static_cast<std::size_t>(
      std::clamp(p * static_cast<double>(v.size() - 1), 0.0, static_cast<double>(v.size() - 1)));
  return v[k];
}

nlohmann::json p50_p99(const std::vector<double>& v) {
  if (v.empty()) return nullptr;
  return {{"p50", percentile(v, 0.5)}, {"p99", percentile(v, 0.99)}, {"n", v.size()}};
}

struct PendingPrediction {
  double t_eval_s;
  int horizon;
  Eigen::Vector3d predicted_mm;
  std::vector<Eigen::Vector3d> goals_mm;  // every goal point's predicted position, base, mm
};

struct World {
  std::mutex mutex;
  RamboCell cell;
  arm::Puma560 arm;
  TumblingBody body;
  std::optional<Rm501Carrier> carrier;  // when set, the target rides on it instead of tumbling
  DiodeIndicator indicator;
  sim::ArmServo servo;
  std::optional<sim::JointTrajectory> pending;
  double clock_s = 0.0;
  int64_t wall0_us = 0, mono0_ns = 0;
  int ticks = 0;
  int logged_tagged = 0;
  double all_tagged_s = -1.0;  // when every diode was first tagged (the first round)
  double round_done_s = -1.0;  // when every diode was tagged in this round
  int rounds_done = 0;
  std::atomic<int64_t> frames{0}, refused{0};
  // Summary material.
  std::map<int64_t, Eigen::Isometry3d> truth_by_utime;  // frame capture -> target in base
  std::vector<double> pose_err_mm, pose_err_deg, pose_ms;
  // Ours by frame (capture utime -> mm, deg, ms) for the peer's frames, and
  // the peer's (RAMBO_POSE_PEER) and ours on the same frames.
  std::map<int64_t, std::array<double, 3>> ours_by_utime;
  std::vector<double> peer_err_mm, peer_err_deg, peer_ms, ours_err_mm, ours_err_deg, ours_ms;
  int64_t peer_poses = 0, peer_found = 0;
  int64_t poses = 0, poses_found = 0, predictions = 0, bad_messages = 0;
  std::string prediction_model;  // the predictor's model (rambo_prediction_t.model), last seen
  std::deque<PendingPrediction> pending_predictions;
  std::vector<double> prediction_err_mm[3];
  std::vector<double> goal_prediction_err_mm[3];  // pooled over the goal points
  std::optional<rambo_plan_t> first_order, last_plan;
  // The schedulers' newest status per host (rt, deadline misses so far) and
  // per process/task (execution time, jobs, misses), from EPHOR_SCHED_STATUS.
  std::map<std::string, std::pair<bool, int64_t>> sched_hosts;
  nlohmann::json sched_tasks = nlohmann::json::object();

  World(RamboCell c, const TumblingMotion& m, const arm::JointLimits& limits)
      : cell(std::move(c)),
        arm(cell.tool_length_mm, limits),
        body(m.pose0, m.velocity_mm_s, m.body_rates_rad_s, cell.principal_moments),
        indicator(cell.diodes, RamboCell::kAcceptanceDeg, RamboCell::kLensRadiusMm,
                  RamboCell::kRequiredS),
        servo(limits, cell.start_joints) {}

  // The target in the base frame at t (mm), and its angular velocity (target frame, rad/s).
  Eigen::Isometry3d target_at(double t_s) { return carrier ? carrier->pose(t_s) : body.pose(t_s); }
  Eigen::Vector3d target_rates_at(double t_s) {
    return carrier ? carrier->body_rates(t_s) : body.body_rates(t_s);
  }

  int64_t utime_of(double t_s) const { return wall0_us + std::llround(t_s * 1e6); }
  double t_of(int64_t utime) const { return static_cast<double>(utime - wall0_us) * 1e-6; }

  // One 1 ms step (caller holds the mutex).
  void step() {
    if (pending) {
      servo.follow(*pending);
      pending.reset();
    }
    servo.step(kStepS);
    clock_s += kStepS;
    const Eigen::Isometry3d target = target_at(clock_s);
    const Eigen::Isometry3d tool = arm.forward(servo.state().q);
    indicator.step(clock_s, target, tool.translation(), tool.linear().col(2));
    while (!pending_predictions.empty() && pending_predictions.front().t_eval_s <= clock_s) {
      const auto& p = pending_predictions.front();
      prediction_err_mm[p.horizon].push_back((p.predicted_mm - target.translation()).norm());
      for (std::size_t i = 0; i < p.goals_mm.size(); ++i)
        goal_prediction_err_mm[p.horizon].push_back(
            (p.goals_mm[i] - (target * cell.goal_in_target(static_cast<int>(i))).translation())
                .norm());
      pending_predictions.pop_front();
    }
    if (indicator.tagged_count() != logged_tagged) {
      logged_tagged = indicator.tagged_count();
      spdlog::info("diode {} tagged at {:.2f} s ({} of {})", indicator.lit_diode(), clock_s,
                   logged_tagged, indicator.size());
      if (logged_tagged == indicator.size()) {
        if (all_tagged_s < 0) all_tagged_s = clock_s;
        round_done_s = clock_s;
      }
    }
  }

  std::string features_source = "none heard";  // of the poses' features

  nlohmann::json summary(uint64_t seed, double spin_deg_s) const {
    nlohmann::json j;
    j["system"] = "rambo";
    j["seed"] = seed;
    j["spin_deg_s"] = spin_deg_s;
    j["carrier"] = carrier ? "rm501" : "free";
    j["diodes"] = indicator.size();
    j["tagged"] = indicator.tagged_count();
    j["rounds_completed"] = rounds_done;
    j["time_to_all_s"] = all_tagged_s >= 0 ? nlohmann::json(all_tagged_s) : nlohmann::json(nullptr);
    nlohmann::json tasks = nlohmann::json::array();
    std::vector<std::pair<double, int>> done;
    for (int i = 0; i < indicator.size(); ++i)
      if (indicator.tagged(i)) done.emplace_back(indicator.tagged_at_s(i), i);
    std::sort(done.begin(), done.end());
    // Per task: its place in the order carried out and its time, from the
    // tag before it (the run's start for the first) to its own tag, s.
    double previous_s = 0.0;
    for (const auto& [t, i] : done) {
      tasks.push_back({{"order", tasks.size() + 1},
                       {"diode", i},
                       {"name", cell.diodes[static_cast<std::size_t>(i)].name},
                       {"tagged_s", t},
                       {"time_s", t - previous_s}});
      previous_s = t;
    }
    j["tasks"] = tasks;
    j["diode_acceptance_deg"] = indicator.acceptance_deg();
    j["diode_lens_radius_mm"] = indicator.lens_radius_mm();
    j["diode_required_s"] = indicator.required_s();
    j["poses"] = poses;
    j["poses_found"] = poses_found;
    j["pose_error_mm"] = p50_p99(pose_err_mm);
    j["pose_error_deg"] = p50_p99(pose_err_deg);
    j["pose_ms"] = p50_p99(pose_ms);
    j["pose_features_source"] = features_source;
    j["predictions"] = predictions;
    nlohmann::json pe;
    for (int h = 0; h < 3; ++h)
      pe[fmt::format("{:.1f}s", kHorizonsS[h])] = p50_p99(prediction_err_mm[h]);
    j["prediction_error_mm"] = pe;
    nlohmann::json ge;
    for (int h = 0; h < 3; ++h)
      ge[fmt::format("{:.1f}s", kHorizonsS[h])] = p50_p99(goal_prediction_err_mm[h]);
    j["goal_prediction_error_mm"] = ge;
    j["prediction_error_of"] =
        "the target frame's origin (prediction_error_mm) and every goal point "
        "(goal_prediction_error_mm, pooled), by the predictor's model (prediction_model)";
    j["prediction_model"] = prediction_model;
    if (first_order) {
      j["reaching_trajectories_computed"] = {{"greedy", first_order->greedy_trajectories},
                                             {"exhaustive", first_order->exhaustive_trajectories},
                                             {"dynamic_programming", first_order->dp_trajectories},
                                             {"tasks", first_order->num_tasks}};
      j["planned_order"] = first_order->order;
    } else {
      j["reaching_trajectories_computed"] = nullptr;
    }
    j["goals_sent"] = last_plan ? last_plan->goals_sent : 0;
    j["frames"] = frames.load();
    j["trajectories_refused"] = refused.load();
    j["bad_messages"] = bad_messages;
    // Summed over the hosts' schedulers; rt only when every host ran its
    // SCHED_FIFO tasks as such (null: no scheduler status heard).
    int64_t misses = 0;
    bool rt = true;
    for (const auto& [host, h] : sched_hosts) {
      rt = rt && h.first;
      misses += h.second;
    }
    j["deadline_misses"] = sched_hosts.empty() ? nlohmann::json(nullptr) : nlohmann::json(misses);
    j["rt"] = sched_hosts.empty() ? nlohmann::json(nullptr) : nlohmann::json(rt);
    j["sched_hosts"] = sched_hosts.size();
    j["sched_tasks"] = sched_tasks;
    // The peer (OpenCV solvePnPRansac over all point-vertex pairs) on the
    // frames ephor-rambo-pose gave it (--peer-every), and ours on the same
    // frames (those where both found a pose).
    j["peer"] = {{"method", "cv::solvePnPRansac AP3P over every image point x model vertex"},
                 {"poses", peer_poses},
                 {"found_with_ours", peer_found},
                 {"pose_error_mm", p50_p99(peer_err_mm)},
                 {"pose_error_deg", p50_p99(peer_err_deg)},
                 {"pose_ms", p50_p99(peer_ms)},
                 {"ours_pose_error_mm", p50_p99(ours_err_mm)},
                 {"ours_pose_error_deg", p50_p99(ours_err_deg)},
                 {"ours_pose_ms", p50_p99(ours_ms)}};
    return j;
  }
};

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
    World w(cell, motion, arm::make_puma(workcell).limits());
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

    auto camera_in_base = [&w](const arm::Joints& q) {
      return w.arm.forward(q) * w.cell.camera_in_tool;
    };
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
      const Eigen::Isometry3d camera0 = camera_in_base(cell.start_joints);
      renderer.render(camera0.inverse() * w.target_at(0.0), image, links_in_camera(chain, camera0));
      cv::imwrite(png_path, image);
      spdlog::info("wrote {}", png_path);
      return 0;
    }

    Bus bus(args.lcm_url, args.name);
    TaskRuntime runtime(bus, {args.name, args.host, !args.no_mlock});

    bus.subscribe<joint_trajectory_t>(
        ephor::channels::kArmTrajectory, [&w](const joint_trajectory_t& m) {
          std::string why;
          auto t = sim::to_trajectory(m, why);
          if (!t) {
            ++w.refused;
            spdlog::warn("ARM_TRAJECTORY seq {} ignored: {}", m.seq, why);
            return;
          }
          std::lock_guard<std::mutex> lock(w.mutex);
          w.pending = std::move(*t);
        });
    bus.subscribe<rambo_pose_t>(rambo::channels::kPose, [&w](const rambo_pose_t& m) {
      std::lock_guard<std::mutex> lock(w.mutex);
      ++w.poses;
      w.features_source = m.features_source;
      if (!m.found) return;
      const Eigen::Isometry3d est = geometry::pose_of(m.target_r, m.target_t_mm);
      const auto it = w.truth_by_utime.find(m.utime);
      if (!est.matrix().allFinite() || it == w.truth_by_utime.end() || !std::isfinite(m.pose_ms)) {
        ++w.bad_messages;
        return;
      }
      ++w.poses_found;
      w.pose_err_mm.push_back((est.translation() - it->second.translation()).norm());
      w.pose_err_deg.push_back(rotation_angle_between(est.linear(), it->second.linear()) * 180.0 /
                               M_PI);
      w.pose_ms.push_back(m.pose_ms);
      w.ours_by_utime[m.utime] = {w.pose_err_mm.back(), w.pose_err_deg.back(), m.pose_ms};
      while (w.ours_by_utime.size() > 100) w.ours_by_utime.erase(w.ours_by_utime.begin());
    });
    bus.subscribe<rambo_pose_t>(rambo::channels::kPosePeer, [&w](const rambo_pose_t& m) {
      std::lock_guard<std::mutex> lock(w.mutex);
      ++w.peer_poses;
      const auto truth = w.truth_by_utime.find(m.utime);
      const auto ours = w.ours_by_utime.find(m.utime);
      if (!m.found || truth == w.truth_by_utime.end() || ours == w.ours_by_utime.end()) return;
      const Eigen::Isometry3d est = geometry::pose_of(m.target_r, m.target_t_mm);
      if (!est.matrix().allFinite() || !std::isfinite(m.pose_ms)) {
        ++w.bad_messages;
        return;
      }
      ++w.peer_found;
      w.peer_err_mm.push_back((est.translation() - truth->second.translation()).norm());
      w.peer_err_deg.push_back(rotation_angle_between(est.linear(), truth->second.linear()) *
                               180.0 / M_PI);
      w.peer_ms.push_back(m.pose_ms);
      w.ours_err_mm.push_back(ours->second[0]);
      w.ours_err_deg.push_back(ours->second[1]);
      w.ours_ms.push_back(ours->second[2]);
    });
    bus.subscribe<rambo_prediction_t>(
        rambo::channels::kPrediction, [&w](const rambo_prediction_t& m) {
          if (!m.fitted) return;
          const std::optional<FittedMotion> f = motion_from_message(m, 0.0, nullptr);
          std::lock_guard<std::mutex> lock(w.mutex);
          if (!f) {
            ++w.bad_messages;
            return;
          }
          ++w.predictions;
          w.prediction_model = m.model;
          const double t_ref = w.t_of(m.ref_utime);
          for (int h = 0; h < 3; ++h) {
            const Eigen::Isometry3d pose = f->pose(kHorizonsS[h]);
            std::vector<Eigen::Vector3d> goals;
            for (int i = 0; i < w.indicator.size(); ++i)
              goals.push_back((pose * w.cell.goal_in_target(i)).translation());
            w.pending_predictions.push_back(
                {t_ref + kHorizonsS[h], h, pose.translation(), std::move(goals)});
          }
          std::sort(w.pending_predictions.begin(), w.pending_predictions.end(),
                    [](const PendingPrediction& a, const PendingPrediction& b) {
                      return a.t_eval_s < b.t_eval_s;
                    });
        });
    bus.subscribe<sched_status_t>(ephor::channels::kSchedStatus, [&w](const sched_status_t& m) {
      int64_t misses = 0;
      for (const auto& t : m.tasks) misses += t.deadline_misses;
      std::lock_guard<std::mutex> lock(w.mutex);
      w.sched_hosts[m.host] = {m.rt != 0, misses};
      for (const auto& t : m.tasks)
        w.sched_tasks[t.process + "/" + t.task] = {
            {"exec_p50_ms", static_cast<double>(t.exec_p50_us) / 1e3},
            {"exec_p99_ms", static_cast<double>(t.exec_p99_us) / 1e3},
            {"jobs", t.jobs},
            {"deadline_misses", t.deadline_misses},
            {"rt", t.rt_granted != 0}};
    });
    bus.subscribe<rambo_plan_t>(rambo::channels::kPlan, [&w](const rambo_plan_t& m) {
      std::lock_guard<std::mutex> lock(w.mutex);
      if (!w.first_order && m.dp_trajectories > 0) w.first_order = m;
      w.last_plan = m;
    });

    w.wall0_us = wall_us();
    w.mono0_ns = mono_ns();
    auto advance_to_now = [&w] {
      const double now_s = static_cast<double>(mono_ns() - w.mono0_ns) * 1e-9;
      if (now_s - w.clock_s > kMaxLagS) {
        spdlog::warn("physics {:.3f} s behind the clock; skipping ahead", now_s - w.clock_s);
        w.clock_s = now_s - kStepS;
      }
      while (w.clock_s + kStepS <= now_s) w.step();
    };

    runtime.add_periodic("physics", std::chrono::milliseconds(2), [&] {
      joint_state_t m;
      {
        std::lock_guard<std::mutex> lock(w.mutex);
        advance_to_now();
        if (++w.ticks % 2 != 0) return;  // ARM_SERVO at 250 Hz
        m = sim::to_joint_state(w.servo.state(), w.utime_of(w.clock_s));
      }
      bus.publish(ephor::channels::kArmServo, m);
    });

    runtime.add_periodic("camera", std::chrono::nanoseconds(static_cast<int64_t>(1e9 / fps)), [&] {
      rambo_truth_t truth{};
      Eigen::Isometry3d target, camera;
      std::vector<Eigen::Vector3d> carrier_chain;  // the RM-501's links, base, mm
      {
        std::lock_guard<std::mutex> lock(w.mutex);
        advance_to_now();
        target = w.target_at(w.clock_s);
        if (w.carrier) {
          const auto c = w.carrier->chain(w.clock_s);
          carrier_chain.assign(c.begin(), c.end());
        }
        camera = camera_in_base(w.servo.state().q);
        truth.utime = w.utime_of(w.clock_s);
        const Eigen::Vector3d rates = w.target_rates_at(w.clock_s);
        for (int k = 0; k < 3; ++k) truth.body_rates_rad_s[k] = rates[k];
        w.truth_by_utime[truth.utime] = target;
        while (w.truth_by_utime.size() > 600) w.truth_by_utime.erase(w.truth_by_utime.begin());
      }
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
    int64_t indicator_ticks = 0;
    runtime.add_periodic("indicator", std::chrono::milliseconds(50), [&] {
      rambo_indicator_t m{};
      {
        std::lock_guard<std::mutex> lock(w.mutex);
        advance_to_now();
        const DiodeIndicator& ind = w.indicator;
        m.utime = w.utime_of(w.clock_s);
        m.num_diodes = ind.size();
        m.lit_diode = ind.lit_diode();
        m.lit_s = ind.lit_s();
        m.tagged_count = ind.tagged_count();
        m.acceptance_deg = ind.acceptance_deg();
        m.lens_radius_mm = ind.lens_radius_mm();
        m.required_s = ind.required_s();
        for (int i = 0; i < ind.size(); ++i) {
          m.tagged.push_back(ind.tagged(i));
          m.tagged_utime.push_back(
              ind.tagged(i) ? static_cast<double>(w.utime_of(ind.tagged_at_s(i))) : 0.0);
          m.beam_angle_deg.push_back(ind.readings()[static_cast<std::size_t>(i)].beam_angle_deg);
          m.beam_offset_mm.push_back(
              std::min(ind.readings()[static_cast<std::size_t>(i)].beam_offset_mm, 1e6));
        }
        if (++indicator_ticks % 100 == 0) {  // every 5 s: how close the beam is to each diode
          std::string line;
          for (int i = 0; i < ind.size(); ++i)
            line += fmt::format(
                " {} {:.1f} deg {:.0f} mm{};", w.cell.diodes[static_cast<std::size_t>(i)].name,
                m.beam_angle_deg[static_cast<std::size_t>(i)],
                m.beam_offset_mm[static_cast<std::size_t>(i)], ind.tagged(i) ? " (tagged)" : "");
          spdlog::info("beam at {:.0f} s:{}", w.clock_s, line);
        }
        if (w.round_done_s >= 0 && w.clock_s > w.round_done_s + 1.0) {
          ++w.rounds_done;
          if (rounds == 0 || w.rounds_done < rounds) {
            spdlog::info("round {} done at {:.1f} s: every diode untagged, the next round starts",
                         w.rounds_done, w.clock_s);
            w.indicator.reset_tags(w.clock_s);
            w.round_done_s = -1.0;
            w.logged_tagged = 0;
          } else {
            finished = true;
          }
        }
        if (w.clock_s > max_s) finished = true;
      }
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
    spdlog::info("summary: {}", s.dump());
    if (!summary_path.empty()) {
      std::ofstream out(summary_path);
      out << s.dump(2) << "\n";
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
