// Fuzz target (issue 18): ephor-calibrate's handlers and what its procedure
// makes of them, on any interleaved stream of CAMERA (camera_frame_t) and
// ARM_SERVO (joint_state_t) messages: each decoded the way the bus does (a
// message that does not decode to its full size is dropped) and handed to
// CellInputs::on_frame() or on_state() (calibrate_messages.h), and, as the
// Calibrator in main.cc uses the newest of each: a move to a stop of the
// CalibrationPlan or to the park pose (inverse kinematics of the tool-down
// pose nearest the servo's joints, JointMove::plan from move_start_of() at
// --speed 0.5, 1 or 0.05, the ARM_TRAJECTORY of trajectory_message_of()), and a
// dark / lit frame pair to ToolSpotFinder::find() with the tip where the
// servo's joints put it (tool_in_field()).
//
// Checks: a frame is dropped (and counted) exactly when its size does not
// match its data, a state exactly when a joint is not finite, and what is
// kept is the newest; a move the procedure cannot plan ends it with an
// error that says why (the process turns the light off and exits 1), and
// every trajectory it would publish is finite, starts at 0 s and at the
// servo's joints, increases in time, stays within the joint limits and
// within --speed of the speed limit, ends at the goal, encodes, and is one
// the servo (ArmServo, at the move's start) takes without a fault; a spot
// is inside the image, of the finder's plausible size, and the tip finite;
// no spot comes with its reason.
//
// Input: a FuzzMessageStream (common/fuzz/fuzz_input.h) over 4 channels:
// 0 CAMERA, 1 ARM_SERVO, 2 a move (first byte: value % 3 the speed, value /
// 3 the stop, past the last the park pose), 3 a frame taken (first byte
// bit 0: as the lit frame, with the dark one before it to the finder;
// otherwise as the dark one). Seeds: fuzz_corpus/shepherd_calibrate (made by
// a small generator: the arm parked, moved to stops and parked again; frames
// with and without a light spot; states with NaN, out of the limits and at
// the limits, frames whose size does not match) and the input of the fault
// it found (crash-start-just-above-joint-limit: a servo state within
// JointMove's 1e-6 rad of a limit made a trajectory the servo refuses).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <spdlog/spdlog.h>

#include "common/arm/arm_servo.h"
#include "common/arm/arm_workcell.h"
#include "common/arm/servo_messages.h"
#include "common/fuzz/fuzz_input.h"
#include "common/geometry/workcell.h"
#include "common/shepherd/calibrate/calibration_plan.h"
#include "common/shepherd/calibrate/joint_move.h"
#include "common/shepherd/calibrate/tool_spot_finder.h"
#include "procs/shepherd/calibrate/calibrate_messages.h"

namespace {

using namespace ephor;
using namespace ephor::calibrate;

constexpr double kTol = 1e-6;
constexpr double kSpeeds[3] = {0.5, 1.0, 0.05};

struct Cell {
  geometry::Workcell cell;
  arm::Puma560 puma = arm::make_puma(cell);
  CalibrationPlan plan{cell};
  ToolSpotFinder finder;
};

const Cell& the_cell() {
  static const Cell c;
  return c;
}

// The Calibrator's move_to(ik(tip)) or move_to(park_joints): what it publishes.
void move(const Cell& c, const joint_state_t& state, uint8_t choice) {
  const double speed = kSpeeds[choice % 3];
  const size_t stop = choice / 3;
  const arm::JointLimits& lim = c.puma.limits();
  arm::Joints from;
  try {
    from = move_start_of(state, lim);
  } catch (const std::runtime_error& e) {
    if (lim.within(joints_of(state), 1e-6)) fuzz::fail("a start within the limits refused");
    if (std::string(e.what()).find("joint") == std::string::npos)
      fuzz::fail("a start refused without naming the joint");
    return;  // the procedure ends with the reason, the light off
  }
  if (!lim.within(from)) fuzz::fail("a move's start outside the limits");
  arm::Joints goal;
  if (stop < c.plan.stops().size()) {
    const Eigen::Vector3d tip = c.plan.stops()[stop].tip_mm;
    const auto q = c.puma.nearest_inverse(
        arm::tool_down_pose(c.cell, tip.x(), tip.y(), tip.z(), 0.0), joints_of(state));
    if (!q) return;  // "inverse kinematics failed for ...": the procedure ends
    goal = *q;
  } else {
    goal = arm::park_joints(c.cell);
  }
  JointPath path;
  try {
    path = JointMove::plan(from, goal, lim, speed);
  } catch (const std::invalid_argument& e) {
    if (std::string(e.what()).empty()) fuzz::fail("a move refused without a reason");
    if (lim.within(goal))
      fuzz::fail(std::string("a move between joints within the limits refused: ") + e.what());
    return;  // the procedure ends with the reason, the light off
  }
  const joint_trajectory_t m = trajectory_message_of(path, 1'700'000'000'000'000, 4'000'000'000);
  const size_t n = static_cast<size_t>(m.num_points);
  if (m.num_points < 2 || m.t_s.size() != n || m.q.size() != n || m.qd.size() != n)
    fuzz::fail("a trajectory whose sizes disagree");
  for (size_t i = 0; i < n; ++i) {
    if (!std::isfinite(m.t_s[i]) || (i == 0 && m.t_s[i] != 0.0f) ||
        (i > 0 && !(m.t_s[i] > m.t_s[i - 1])))
      fuzz::fail("a trajectory's times are not 0, increasing");
    for (size_t j = 0; j < 6; ++j) {
      const double q = m.q[i][j], qd = m.qd[i][j];
      if (!std::isfinite(q) || q < lim.q_min(j) - kTol || q > lim.q_max(j) + kTol)
        fuzz::fail("a trajectory point: joint " + std::to_string(j + 1) + " at " +
                   std::to_string(q) + " rad, outside its limits");
      if (!std::isfinite(qd) || std::abs(qd) > speed * lim.qd_max(j) + kTol)
        fuzz::fail("a trajectory point: joint " + std::to_string(j + 1) + " at " +
                   std::to_string(qd) + " rad/s, above --speed of its limit");
    }
  }
  for (int j = 0; j < 6; ++j) {
    if (std::abs(m.q.front()[static_cast<size_t>(j)] - from(j)) > kTol)
      fuzz::fail("a trajectory that does not start at the servo's joints");
    if (std::abs(m.q.back()[static_cast<size_t>(j)] - goal(j)) > kTol)
      fuzz::fail("a trajectory that does not end at the goal");
  }
  const int size = m.getEncodedSize();
  std::vector<uint8_t> bytes(static_cast<size_t>(size));
  if (m.encode(bytes.data(), 0, size) != size) fuzz::fail("the trajectory does not encode");

  std::string why;
  const auto t = sim::to_trajectory(m, why);
  if (!t) fuzz::fail("a trajectory the servo refuses as malformed: " + why);
  sim::ArmServo servo(lim, from);
  if (!servo.follow(*t) || servo.state().fault)
    fuzz::fail("a trajectory the servo faults: " + servo.state().fault_reason);
}

void find_spot(const Cell& c, const GreyFrame& lit, const GreyFrame& dark,
               const joint_state_t& state) {
  const SpotResult r = c.finder.find(lit, dark);
  if (!r.spot) {
    if (r.reason.empty()) fuzz::fail("no spot and no reason");
    return;
  }
  const ToolSpot& s = *r.spot;
  if (!r.reason.empty()) fuzz::fail("a spot with a reason");
  if (!s.centre_px.allFinite() || s.centre_px.x() < -0.5 || s.centre_px.y() < -0.5 ||
      s.centre_px.x() > lit.width - 0.5 || s.centre_px.y() > lit.height - 0.5)
    fuzz::fail("a spot outside the image");
  const ToolSpotFinderConfig& k = c.finder.config();
  if (!(s.area_px >= k.min_area_px && s.area_px <= k.max_area_px))
    fuzz::fail("a spot of an implausible size");
  if (!std::isfinite(s.contrast)) fuzz::fail("a spot's contrast that is not finite");
  if (!arm::tool_in_field(c.cell, joints_of(state)).tip_mm.allFinite())
    fuzz::fail("a tip that is not finite");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const bool quiet = [] {
    spdlog::set_level(spdlog::level::off);
    return true;
  }();
  (void)quiet;
  const Cell& c = the_cell();
  CellInputs inputs;
  std::optional<GreyFrame> dark;
  fuzz::FuzzMessageStream stream(data, size, 4, 8192, 64);
  fuzz::FuzzMessage msg;
  while (stream.next(msg)) {
    switch (msg.channel) {
      case 0: {
        camera_frame_t m;
        if (!msg.decode(m)) break;
        const int64_t bad = inputs.bad_frames();
        const bool whole =
            m.width > 0 && m.height > 0 &&
            m.data.size() == static_cast<size_t>(m.width) * static_cast<size_t>(m.height);
        if (inputs.on_frame(m) != whole || inputs.bad_frames() != bad + (whole ? 0 : 1))
          fuzz::fail("a frame kept or dropped against its size, or uncounted");
        if (whole &&
            (inputs.frame_utime() != m.utime || inputs.frame().data.size() != m.data.size()))
          fuzz::fail("a frame kept is not the newest");
        break;
      }
      case 1: {
        joint_state_t m;
        if (!msg.decode(m)) break;
        bool finite = true;
        for (double q : m.q) finite = finite && std::isfinite(q);
        if (inputs.on_state(m) != finite) fuzz::fail("a state kept or dropped against its joints");
        const auto s = inputs.state();
        if (finite && (!s || s->utime != m.utime)) fuzz::fail("a state kept is not the newest");
        if (s && !joints_of(*s).allFinite()) fuzz::fail("a state kept that is not finite");
        break;
      }
      case 2: {
        const auto s = inputs.state();
        if (s) move(c, *s, msg.size > 0 ? msg.bytes[0] : 0);
        break;
      }
      default: {
        const auto s = inputs.state();
        if (!s || inputs.frame_utime() == 0) break;  // check_inputs() waits for both
        const bool lit = msg.size > 0 && (msg.bytes[0] & 1) != 0;
        if (!lit) {
          dark = inputs.frame();
        } else if (dark) {
          find_spot(c, inputs.frame(), *dark, *s);
        }
        break;
      }
    }
  }
  return 0;
}
