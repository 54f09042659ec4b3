// Fuzz target (issue 18): ephor-sim's bus handlers and tasks on any
// interleaved stream of ARM_TRAJECTORY (joint_trajectory_t), SIM_CMD
// (shepherd_sim_cmd_t) and SIM_TOOL_LIGHT (shepherd_tool_light_t) messages
// and camera frames, as the process runs them (sim_messages.h): each message
// decoded the way the bus does (a message that does not decode to its full
// size is dropped) and handed to SimInputs::on_trajectory() (a trajectory it
// passes waits in the servo task's one-trajectory mailbox, overwritten by a
// newer one), on_command() or on_tool_light(); on a monotonic clock that
// moves by 0-262 ms a message, the physics task (advance_to()) and the servo
// task (Simulator::follow() of the waiting trajectory, the ARM_SERVO state
// as to_joint_state() publishes it) every 4 ms, or, when the tasks were
// starved, once late (the physics then skips ahead past 0.5 s); a camera
// frame rendered as the camera task does (Simulator::render(), the
// GROUND_TRUTH of ground_truth_message_of()). The process's defaults
// (--sheep 4 --seed 1), or --clouds 3, but a camera of a quarter of the
// resolution (128 x 120 px, the same view): its per-pixel set-up took most
// of an input's time under ASan.
//
// Checks: a refused trajectory is counted and does not reach the servo; a
// trajectory the servo does not take is a duplicate seq or leaves the
// servo faulted with a reason; the arm's state is finite, within the
// PUMA's joint position and speed limits and moved no faster and
// accelerated no harder than the limits since the last period; a refused
// SIM_CMD is counted and an accepted one leaves at most the herd it asks
// for; the ground truth is finite, has every sheep of the world, and the
// servo state and the ground truth encode.
//
// Input: one byte of settings (bit 0: --clouds 3), then a FuzzMessageStream
// (common/fuzz/fuzz_input.h) over 8 channels: value % 4: 0 ARM_TRAJECTORY,
// 1 SIM_CMD, 2 SIM_TOOL_LIGHT, 3 a camera frame (its bytes are ignored; at
// most 4 an input: rendering is the slow part); value / 4 = 1: the tasks did
// not run during this record's clock step. At most 4 s of simulated time an
// input (the stream ends there). Seeds: fuzz_corpus/shepherd_sim (made by a
// small generator: the arm moving out of park and back with frames taken, a
// herd resized and reset with new seeds, the light switched; trajectories
// malformed, out of the limits, repeated and overwritten; starved tasks)
// and crash-light-on-byte-2, an LCM boolean of 2: the light goes on, as for
// 1 (the fault was this target's, which compared the byte with the light);
// crash-timeout-servo-reason-every-step, a trajectory asking ~1e300 rad/s
// whose fault reason ArmServo formatted at every 1 ms step (30 s for an
// input under ASan; fixed in aec2577, found there by catch_sim).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <spdlog/spdlog.h>

#include "common/arm/servo_messages.h"
#include "common/fuzz/fuzz_input.h"
#include "common/shepherd/sim/simulator.h"
#include "ephor/joint_state_t.hpp"
#include "procs/shepherd/sim/sim_messages.h"

namespace {

using namespace ephor;
using namespace ephor::sim;

constexpr int64_t kPeriodUs = 4000;  // the physics and servo tasks' period
constexpr int64_t kMaxSimUs = 4'000'000;
constexpr int kMaxFrames = 4;
constexpr double kTol = 1e-6;

struct Run {
  Simulator sim;
  SimInputs inputs;
  CameraRenderer& camera;
  double clock_s = 0.0;
  int64_t now_us = 0;
  int64_t next_period_us = kPeriodUs;
  std::optional<JointTrajectory> pending;
  std::optional<ServoState> last;  // the servo at the last period
  double last_s = 0.0;
  int frames = 0;

  Run(const SimulatorConfig& c, CameraRenderer& cam) : sim(c), camera(cam) {}

  // The physics task, then the servo task, at `t_us` on the clock.
  void period(int64_t t_us) {
    advance_to(sim, clock_s, static_cast<double>(t_us) * 1e-6);
    if (pending) {
      const int64_t seq_before = sim.servo().trajectory_seq;
      const bool taken = sim.follow(*pending);
      const ServoState& s = sim.servo();
      if (!taken && !(pending->seq == seq_before && seq_before != 0) &&
          !(s.fault && !s.fault_reason.empty()))
        fuzz::fail("a trajectory the servo did not take, neither a repeat nor a fault");
      pending.reset();
    }
    check_servo(sim.servo());
  }

  void check_servo(const ServoState& s) {
    const arm::JointLimits& lim = sim.puma().limits();
    for (int j = 0; j < 6; ++j) {
      const std::string joint = "joint " + std::to_string(j + 1);
      if (!std::isfinite(s.q(j)) || !std::isfinite(s.qd(j)))
        fuzz::fail(joint + ": a state that is not finite");
      if (s.q(j) < lim.q_min(j) - kTol || s.q(j) > lim.q_max(j) + kTol)
        fuzz::fail(joint + " at " + std::to_string(s.q(j)) + " rad, outside its limits");
      if (std::abs(s.qd(j)) > lim.qd_max(j) + kTol)
        fuzz::fail(joint + " at " + std::to_string(s.qd(j)) + " rad/s, above its speed limit");
      if (last) {
        const double dt = clock_s - last_s;
        if (std::abs(s.q(j) - last->q(j)) > lim.qd_max(j) * dt + kTol)
          fuzz::fail(joint + " moved faster than its speed limit");
        if (std::abs(s.qd(j) - last->qd(j)) > lim.qdd_max(j) * dt + kTol)
          fuzz::fail(joint + " accelerated harder than its limit");
      }
    }
    if (s.fault && s.fault_reason.empty()) fuzz::fail("a servo fault without a reason");
    joint_state_t m = to_joint_state(s, 1'700'000'000'000'000 + now_us);
    fuzz::check_encodes(m, "the servo state");
    last = s;
    last_s = clock_s;
  }

  // The camera task.
  void frame() {
    advance_to(sim, clock_s, static_cast<double>(now_us) * 1e-6);
    const Scene scene = sim.scene();
    std::vector<uint8_t> image;
    const GroundTruth gt = Simulator::render(scene, camera, image);
    if (image.size() != static_cast<size_t>(camera.width()) * static_cast<size_t>(camera.height()))
      fuzz::fail("a frame whose size is not width * height");
    const shepherd_ground_truth_t m = ground_truth_message_of(gt, 1'700'000'000'000'000, frames);
    if (m.num_sheep != static_cast<int32_t>(scene.sheep.size()))
      fuzz::fail("a ground truth that misses sheep");
    if (!std::isfinite(m.sim_time_s)) fuzz::fail("a ground truth time that is not finite");
    for (const auto& s : m.sheep)
      if (!std::isfinite(s.x_mm) || !std::isfinite(s.y_mm) || !std::isfinite(s.heading_rad) ||
          !std::isfinite(s.speed_mm_s) || !std::isfinite(s.u) || !std::isfinite(s.v))
        fuzz::fail("a sheep's ground truth that is not finite");
    fuzz::check_encodes(m, "the ground truth");
    ++frames;
  }
};

SimulatorConfig config_of(uint8_t settings) {
  SimulatorConfig c;  // ephor-sim's defaults: --sheep 4 --seed 1 --noise 2.5
  c.world.sheep = 4;
  c.world.seed = 1;
  c.world.speed_mm_s = 8.0;
  c.world.reentry_s = 5.0;
  c.camera.noise_sigma = 2.5;
  c.camera.seed = 1;
  c.clouds.seed = 1;
  // The same view at a quarter of the resolution (see above).
  geometry::OverheadCamera& cam = c.camera.camera;
  cam.width_px /= 4;
  cam.height_px /= 4;
  cam.focal_px /= 4.0;
  cam.cu_px = 0.5 * (cam.width_px - 1);
  cam.cv_px = 0.5 * (cam.height_px - 1);
  if ((settings & 1) != 0) c.clouds.clouds = 3;
  return c;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  // The handlers' log lines (a refused trajectory, a reset) would only slow the run.
  static const bool quiet = [] {
    spdlog::set_level(spdlog::level::off);
    return true;
  }();
  (void)quiet;
  if (size < 1) return 0;
  // The camera task's renderer, made once (its per-pixel lighting is as slow
  // as the rest of an input); only its noise differs between inputs.
  static CameraRenderer camera(config_of(0).camera, config_of(0).world);
  Run run(config_of(data[0]), camera);
  run.check_servo(run.sim.servo());
  fuzz::FuzzMessageStream stream(data + 1, size - 1, 8);
  fuzz::FuzzMessage msg;
  bool starved = false;
  while (stream.next(msg)) {
    run.now_us += msg.step_us;
    if (run.now_us > kMaxSimUs) break;
    if (msg.channel / 4 == 1) {
      starved = true;
    } else if (starved) {
      // Late tasks run once, then keep their period from now.
      run.period(run.now_us);
      run.next_period_us = run.now_us + kPeriodUs;
      starved = false;
    } else {
      for (; run.next_period_us <= run.now_us; run.next_period_us += kPeriodUs)
        run.period(run.next_period_us);
    }
    switch (msg.channel % 4) {
      case 0: {
        joint_trajectory_t m;
        if (!msg.decode(m)) break;
        const int64_t refused = run.inputs.trajectories_refused();
        auto t = run.inputs.on_trajectory(m);
        if (run.inputs.trajectories_refused() != refused + (t ? 0 : 1))
          fuzz::fail("a trajectory refused uncounted, or taken and counted");
        if (t) run.pending = std::move(*t);
        break;
      }
      case 1: {
        shepherd_sim_cmd_t m;
        if (!msg.decode(m)) break;
        const int64_t refused = run.inputs.commands_refused();
        const bool taken = run.inputs.on_command(m, run.sim);
        if (run.inputs.commands_refused() != refused + (taken ? 0 : 1))
          fuzz::fail("a SIM_CMD refused uncounted, or taken and counted");
        if (taken && static_cast<int64_t>(run.sim.world().sheep().size()) > m.sheep)
          fuzz::fail("more sheep on the field than SIM_CMD asks for");
        if (!taken && (m.sheep >= 0 && m.sheep <= kMaxSheep))
          fuzz::fail("a SIM_CMD within the limits refused");
        break;
      }
      case 2: {
        shepherd_tool_light_t m;
        if (!msg.decode(m)) break;
        run.inputs.on_tool_light(m, run.sim);
        if (run.sim.tool_light() != (m.on != 0)) fuzz::fail("the tool light not as asked");
        break;
      }
      default:
        if (run.frames < kMaxFrames) run.frame();
        break;
    }
  }
  return 0;
}
