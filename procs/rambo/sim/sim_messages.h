#pragma once
// ephor-rambo-sim's world and what its handlers and tasks do with it (out of
// main.cc, so that the fuzz target sim_messages_fuzz.cc runs what the process
// runs): the tumbling (or RM-501-carried) target, its diodes and indicator
// electronics, the PUMA 560's servo layer following ARM_TRAJECTORY, the
// ground truth the camera task records, and the run's summary scored from
// RAMBO_POSE, RAMBO_POSE_PEER, RAMBO_PREDICTION, RAMBO_PLAN and
// EPHOR_SCHED_STATUS against that truth. Base frame, mm, rad, s; the sim's
// clock is seconds since start-up (clock_s), a message's utime is the wall
// clock at start plus it (utime_of).
//
// Threading: the handlers (on_*) and the task steps (physics_tick,
// camera_shot, indicator_tick) take `mutex` themselves; step(), advance_to()
// and summary() want the caller to hold it. No exception escapes a handler:
// a bad message is counted (bad_messages, refused) and dropped.

#include <array>
#include <atomic>
#include <cstdint>
#include <deque>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "common/arm/arm_servo.h"
#include "common/arm/puma560.h"
#include "common/rambo/diode_indicator.h"
#include "common/rambo/rambo_cell.h"
#include "common/rambo/rm501_carrier.h"
#include "common/rambo/tumbling_body.h"
#include "ephor/joint_state_t.hpp"
#include "ephor/joint_trajectory_t.hpp"
#include "ephor/rambo_indicator_t.hpp"
#include "ephor/rambo_plan_t.hpp"
#include "ephor/rambo_pose_t.hpp"
#include "ephor/rambo_prediction_t.hpp"
#include "ephor/rambo_truth_t.hpp"
#include "ephor/sched_status_t.hpp"

namespace ephor::rambo {

constexpr double kSimStepS = 0.001;                  // physics step: servo and indicator
constexpr double kSimMaxLagS = 0.5;                  // physics further behind the clock skips ahead
constexpr double kSimHorizonsS[] = {0.5, 1.0, 2.0};  // predictions scored at these horizons

struct PendingPrediction {
  double t_eval_s;
  int horizon;
  Eigen::Vector3d predicted_mm;
  std::vector<Eigen::Vector3d> goals_mm;  // every goal point's predicted position, base, mm
};

// What the camera task renders and publishes at one frame: the target and
// the camera in the base frame, the carrier's links, and the truth message
// with its utime and body rates set (the rest is the caller's).
struct CameraShot {
  Eigen::Isometry3d target = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d camera = Eigen::Isometry3d::Identity();
  std::vector<Eigen::Vector3d> carrier_chain;  // the RM-501's links, base, mm
  rambo_truth_t truth{};
};

struct SimWorld {
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
  int64_t indicator_ticks = 0;
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
  std::string features_source = "none heard";  // of the poses' features

  SimWorld(RamboCell c, const TumblingMotion& m, const arm::JointLimits& limits);

  // The target in the base frame at t (mm), and its angular velocity (target frame, rad/s).
  Eigen::Isometry3d target_at(double t_s);  // TumblingBody integrates: not const
  Eigen::Vector3d target_rates_at(double t_s);
  // The camera in the base frame with the arm at q (mm).
  Eigen::Isometry3d camera_in_base(const arm::Joints& q) const;

  int64_t utime_of(double t_s) const;
  double t_of(int64_t utime) const;

  // One 1 ms step (caller holds the mutex).
  void step();
  // Physics up to now_s (s since start; caller holds the mutex): 1 ms steps,
  // skipping ahead when more than kSimMaxLagS behind.
  void advance_to(double now_s);

  // Handlers (each takes the mutex).
  void on_trajectory(const joint_trajectory_t& m);  // ARM_TRAJECTORY
  void on_pose(const rambo_pose_t& m);              // RAMBO_POSE
  void on_pose_peer(const rambo_pose_t& m);         // RAMBO_POSE_PEER
  void on_prediction(const rambo_prediction_t& m);  // RAMBO_PREDICTION
  void on_sched_status(const sched_status_t& m);    // EPHOR_SCHED_STATUS
  void on_plan(const rambo_plan_t& m);              // RAMBO_PLAN

  // Task "physics" (2 ms): advances to now_s; every second call, the
  // ARM_SERVO to publish (250 Hz).
  std::optional<joint_state_t> physics_tick(double now_s);
  // Task "camera": advances to now_s and records the truth of the frame.
  CameraShot camera_shot(double now_s);
  // Task "indicator" (50 ms): advances to now_s, the RAMBO_INDICATOR to
  // publish; ends a round one second after its last tag (`rounds`: 0 =
  // endless), and sets `finished` after the last round or past max_s.
  rambo_indicator_t indicator_tick(double now_s, int rounds, double max_s, bool& finished);

  // The run's summary (caller holds the mutex). Strings in it come from the
  // bus (a host, a task, a features source: any bytes): write it with
  // json_text (common/log/json_text.h), as nlohmann's dump() throws on bytes
  // that are not UTF-8 and the summary would be lost at exit.
  nlohmann::json summary(uint64_t seed, double spin_deg_s) const;
};

}  // namespace ephor::rambo
