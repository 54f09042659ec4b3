// Fuzz target (issue 18): ephor-rambo-sim (SimWorld, sim_messages.h) on any
// interleaved stream of the messages it subscribes to, with its tasks
// released as the runtime would: ARM_TRAJECTORY (joint_trajectory_t),
// RAMBO_POSE and RAMBO_POSE_PEER (rambo_pose_t), RAMBO_PREDICTION
// (rambo_prediction_t), EPHOR_SCHED_STATUS (sched_status_t) and RAMBO_PLAN
// (rambo_plan_t), each decoded as the bus does (a message that does not
// decode to its full size is dropped) and handed to its handler; on a fake
// clock that each record's step moves, the task "physics" every 2 ms
// (SimWorld::physics_tick: the servo and the indicator in 1 ms steps,
// ARM_SERVO every 4 ms), "camera" every 200 ms (camera_shot: the truth the
// poses are scored against; the rendering is left out) and "indicator"
// every 50 ms (indicator_tick, --rounds from the input); at the end the
// summary written as the process writes it. The process's defaults: the
// built-in target with --diodes 1-4 from the input, seed 1, 2 deg/s spin,
// free-floating or carried by the RM-501 (--carrier rm501), the default
// work cell's PUMA 560.
//
// Checked, as a user would:
//  - ARM_SERVO: every joint finite, within [q_min, q_max] and its speed
//    within qd_max; between two states the speed changes by at most
//    qdd_max * dt (the simulated servo's limits, whatever a trajectory asks),
//    but for ArmServo's end stop (a joint driven onto its position limit
//    stops there at once, with a fault; seed end_stop_hit); the message
//    encodes;
//  - an ARM_TRAJECTORY is either taken (pending, with its seq) or refused
//    and counted (trajectories_refused);
//  - RAMBO_POSE / RAMBO_POSE_PEER: each counted; a found pose of a frame
//    with truth is either scored with finite errors or counted bad;
//  - RAMBO_PREDICTION: a fitted one is either taken (counted) or counted bad;
//  - RAMBO_INDICATOR and RAMBO_TRUTH: finite, tagged count within the
//    diodes, lit diode -1 or a diode; both encode;
//  - the summary: written (as main.cc writes it), its counts the ones fed.
//
// Input: a byte of settings (bit 0: --carrier rm501; bits 1-2: --diodes
// 1-4; bit 3: --rounds 0, endless), then a FuzzMessageStream
// (common/fuzz/fuzz_input.h) of up to 256 messages of up to 4096 bytes on
// channels 0 ARM_TRAJECTORY, 1 RAMBO_POSE, 2 RAMBO_POSE_PEER, 3
// RAMBO_PREDICTION, 4 EPHOR_SCHED_STATUS, 5 RAMBO_PLAN; the clock stops at
// kMaxSimS (the physics' 1 ms steps bound a run), and fitted predictions
// past kMaxPredictions are skipped (their propagation bounds it too). A
// pose is scored only against a frame's truth, so the fuzz clock's frames
// are at utimes 1'700'000'000'000'000 + 200'000 k us (k >= 1). Seeds:
// fuzz_corpus/rambo_sim (a trajectory, poses of frames, predictions, a
// scheduler's status and a plan, refusals, the RM-501 and endless rounds;
// made by a small generator; end_stop_hit: a joint driven onto its limit);
// crash-* are the inputs of the faults it found.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <spdlog/fmt/fmt.h>
#include <spdlog/spdlog.h>

#include "common/arm/arm_workcell.h"
#include "common/fuzz/fuzz_input.h"
#include "common/geometry/message_pose.h"
#include "common/geometry/workcell.h"
#include "common/log/json_text.h"
#include "common/rambo/target_model_file.h"
#include "procs/rambo/sim/sim_messages.h"

namespace {

using namespace ephor;
using namespace ephor::rambo;

constexpr int64_t kWallStartUs = 1'700'000'000'000'000;
constexpr int64_t kPhysicsUs = 2'000;
constexpr int64_t kCameraUs = 200'000;  // --fps 5
constexpr int64_t kIndicatorUs = 50'000;
constexpr int64_t kMaxSimUs = 4'000'000;  // kMaxSimS = 4 s
constexpr double kMaxS = 120.0;           // --max-s
constexpr double kTol = 1e-9;
// Fitted predictions fed per input: each propagates the rigid body to three
// horizons, up to RigidBodyPosePredictor::kMaxSteps steps for wild body
// rates (bounded, but 0.1 s a message under ASan); eight already meet every
// other message in every order.
constexpr int kMaxPredictions = 8;

struct ServoCheck {
  arm::JointLimits limits;
  bool have_previous = false;
  double previous_qd[6] = {};
  double previous_s = 0.0;

  void check(const joint_state_t& m, double clock_s) {
    for (int j = 0; j < 6; ++j) {
      if (!std::isfinite(m.q[j]) || !std::isfinite(m.qd[j]))
        fuzz::fail(fmt::format("ARM_SERVO joint {}: not finite", j + 1));
      if (m.q[j] < limits.q_min[j] - kTol || m.q[j] > limits.q_max[j] + kTol)
        fuzz::fail(fmt::format("ARM_SERVO joint {} at {} rad, outside [{}, {}]", j + 1, m.q[j],
                               limits.q_min[j], limits.q_max[j]));
      if (std::abs(m.qd[j]) > limits.qd_max[j] * (1.0 + kTol))
        fuzz::fail(fmt::format("ARM_SERVO joint {} at {} rad/s, above its limit {}", j + 1, m.qd[j],
                               limits.qd_max[j]));
      // The one exception, ArmServo's end stop: a joint driven onto its
      // position limit stops there at once, with a fault (the first fault
      // names the reason, so only the flag is asked).
      const bool end_stop =
          m.fault && m.qd[j] == 0.0 && (m.q[j] == limits.q_min[j] || m.q[j] == limits.q_max[j]);
      if (have_previous && !end_stop) {
        const double dt = clock_s - previous_s;
        if (std::abs(m.qd[j] - previous_qd[j]) > limits.qdd_max[j] * dt * (1.0 + 1e-6) + kTol)
          fuzz::fail(
              fmt::format("ARM_SERVO joint {}: speed changed by {} rad/s in {} s, above "
                          "the acceleration limit {} rad/s^2",
                          j + 1, m.qd[j] - previous_qd[j], dt, limits.qdd_max[j]));
      }
      previous_qd[j] = m.qd[j];
    }
    have_previous = true;
    previous_s = clock_s;
    fuzz::check_encodes(m, "ARM_SERVO");
  }
};

void check_indicator(const rambo_indicator_t& m) {
  if (m.tagged_count < 0 || m.tagged_count > m.num_diodes)
    fuzz::fail(fmt::format("{} of {} diodes tagged", m.tagged_count, m.num_diodes));
  if (m.lit_diode < -1 || m.lit_diode >= m.num_diodes)
    fuzz::fail(fmt::format("lit diode {} of {}", m.lit_diode, m.num_diodes));
  if (!std::isfinite(m.lit_s)) fuzz::fail("a lit time that is not finite");
  for (size_t i = 0; i < m.beam_angle_deg.size(); ++i)
    if (!std::isfinite(m.beam_angle_deg[i]) || !std::isfinite(m.beam_offset_mm[i]) ||
        !std::isfinite(m.tagged_utime[i]))
      fuzz::fail("RAMBO_INDICATOR with a reading that is not finite");
  fuzz::check_encodes(m, "RAMBO_INDICATOR");
}

void check_truth(const CameraShot& shot, SimWorld& w) {
  rambo_truth_t truth = shot.truth;
  geometry::set_pose(shot.target, truth.target_r, truth.target_t_mm);
  geometry::set_pose(shot.camera, truth.camera_r, truth.camera_t_mm);
  for (const Eigen::Vector3d& p : shot.carrier_chain)
    truth.carrier_mm.push_back({p.x(), p.y(), p.z()});
  truth.carrier_points = static_cast<int32_t>(truth.carrier_mm.size());
  truth.frame_index = w.frames;
  if (!fuzz::all_finite(truth.target_r, 9) || !fuzz::all_finite(truth.target_t_mm, 3) ||
      !fuzz::all_finite(truth.camera_r, 9) || !fuzz::all_finite(truth.camera_t_mm, 3) ||
      !fuzz::all_finite(truth.body_rates_rad_s, 3))
    fuzz::fail("RAMBO_TRUTH that is not finite");
  fuzz::check_encodes(truth, "RAMBO_TRUTH");
  ++w.frames;
}

// The newest score a handler added is finite (or nothing was added).
void check_scores(const std::vector<double>& v, size_t before, const char* what) {
  for (size_t i = before; i < v.size(); ++i)
    if (!std::isfinite(v[i])) fuzz::fail(fmt::format("{} scored {}", what, v[i]));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const bool quiet = [] {
    spdlog::set_level(spdlog::level::off);  // the process's log, at every tag and refusal
    return true;
  }();
  (void)quiet;
  if (size < 1) return 0;
  const bool rm501 = (data[0] & 1) != 0;
  const int diodes = 1 + ((data[0] >> 1) & 3);
  const int rounds = (data[0] & 8) != 0 ? 0 : 1;
  static const arm::JointLimits limits = arm::make_puma(geometry::Workcell{}).limits();
  static const RamboCell cells[4] = {cell_from_flags("", 1), cell_from_flags("", 2),
                                     cell_from_flags("", 3), cell_from_flags("", 4)};
  const RamboCell& cell = cells[diodes - 1];
  const uint64_t seed = 1;
  const double spin_deg_s = 2.0;
  const TumblingMotion motion = cell.draw_motion(seed, spin_deg_s, 1.0);
  SimWorld w(cell, motion, limits);
  if (rm501) w.carrier.emplace(motion.pose0, seed, spin_deg_s / 2.0);
  w.wall0_us = kWallStartUs;
  w.mono0_ns = 0;

  ServoCheck servo{limits};
  int64_t clock_us = 0;
  int64_t next_physics = kPhysicsUs, next_camera = kCameraUs, next_indicator = kIndicatorUs;
  bool finished = false;
  // Runs every task released up to `end_us`, in release order.
  const auto run_until = [&](int64_t end_us) {
    for (;;) {
      const int64_t next = std::min({next_physics, next_camera, next_indicator});
      if (next > end_us) break;
      clock_us = next;
      const double now_s = static_cast<double>(clock_us) * 1e-6;
      if (next == next_physics) {
        next_physics += kPhysicsUs;
        if (const auto m = w.physics_tick(now_s)) servo.check(*m, w.clock_s);
      } else if (next == next_camera) {
        next_camera += kCameraUs;
        check_truth(w.camera_shot(now_s), w);
      } else {
        next_indicator += kIndicatorUs;
        check_indicator(w.indicator_tick(now_s, rounds, kMaxS, finished));
      }
    }
    clock_us = end_us;
  };

  int64_t poses = 0, peer_poses = 0, refused = 0;
  int fitted_fed = 0;
  fuzz::FuzzMessageStream stream(data + 1, size - 1, 6);
  fuzz::FuzzMessage msg;
  while (!finished && stream.next(msg)) {
    if (clock_us + msg.step_us > kMaxSimUs) break;
    run_until(clock_us + msg.step_us);
    switch (msg.channel) {
      case 0: {
        joint_trajectory_t m;
        if (!msg.decode(m)) break;
        w.pending.reset();
        w.on_trajectory(m);
        if (w.pending) {
          if (w.pending->seq != m.seq) fuzz::fail("a trajectory taken under another seq");
        } else if (w.refused != ++refused) {
          fuzz::fail("a trajectory dropped uncounted");
        }
        break;
      }
      case 1:
      case 2: {
        rambo_pose_t m;
        if (!msg.decode(m)) break;
        const bool peer = msg.channel == 2;
        const int64_t found_before = peer ? w.peer_found : w.poses_found;
        const int64_t bad_before = w.bad_messages;
        const size_t n = peer ? w.peer_err_mm.size() : w.pose_err_mm.size();
        if (peer) {
          w.on_pose_peer(m);
          if (w.peer_poses != ++peer_poses) fuzz::fail("a peer pose not counted");
          check_scores(w.peer_err_mm, n, "a peer pose's error (mm)");
          check_scores(w.peer_err_deg, n, "a peer pose's error (deg)");
          check_scores(w.peer_ms, n, "a peer pose's time (ms)");
        } else {
          const bool scored = m.found && w.truth_by_utime.count(m.utime) != 0;
          w.on_pose(m);
          if (w.poses != ++poses) fuzz::fail("a pose not counted");
          if (scored && w.poses_found + w.bad_messages != found_before + bad_before + 1)
            fuzz::fail("a found pose of a frame neither scored nor counted bad");
          check_scores(w.pose_err_mm, n, "a pose's error (mm)");
          check_scores(w.pose_err_deg, n, "a pose's error (deg)");
          check_scores(w.pose_ms, n, "a pose's time (ms)");
        }
        break;
      }
      case 3: {
        rambo_prediction_t m;
        if (!msg.decode(m)) break;
        if (m.fitted && ++fitted_fed > kMaxPredictions) break;
        const int64_t before = w.predictions + w.bad_messages;
        w.on_prediction(m);
        if (m.fitted && w.predictions + w.bad_messages != before + 1)
          fuzz::fail("a fitted prediction neither taken nor counted bad");
        break;
      }
      case 4: {
        sched_status_t m;
        if (msg.decode(m)) w.on_sched_status(m);
        break;
      }
      default: {
        rambo_plan_t m;
        if (msg.decode(m)) w.on_plan(m);
        break;
      }
    }
  }
  // The summary, as main.cc writes it at the end of the run.
  const nlohmann::json s = w.summary(seed, spin_deg_s);
  const std::string line = json_text(s);
  const std::string file = json_text(s, 2);
  if (s["poses"] != poses || s["peer"]["poses"] != peer_poses ||
      s["trajectories_refused"] != refused)
    fuzz::fail("the summary's counts are not the messages fed");
  (void)line;
  (void)file;
  for (int h = 0; h < 3; ++h) {
    check_scores(w.prediction_err_mm[h], 0, "a prediction's error (mm)");
    check_scores(w.goal_prediction_err_mm[h], 0, "a goal prediction's error (mm)");
  }
  return 0;
}
