#pragma once
// ephor-calibrate's inputs and the trajectories it publishes (out of
// main.cc, so that the fuzz target calibrate_messages_fuzz.cc runs what the
// process runs): CellInputs keeps the newest CAMERA frame (camera_frame_t)
// whose size matches its data and the newest ARM_SERVO state
// (joint_state_t) whose joints are finite, and counts the frames it drops;
// trajectory_message_of() is the ARM_TRAJECTORY (joint_trajectory_t) of a
// JointMove.
//
// Threading: CellInputs is thread-safe (the bus thread writes, the
// calibration procedure reads).

#include <atomic>
#include <cstdint>
#include <mutex>
#include <optional>
#include <stdexcept>

#include "common/arm/puma560.h"
#include "common/shepherd/calibrate/joint_move.h"
#include "common/shepherd/calibrate/tool_spot_finder.h"
#include "ephor/camera_frame_t.hpp"
#include "ephor/joint_state_t.hpp"
#include "ephor/joint_trajectory_t.hpp"

namespace ephor::calibrate {

class CellInputs {
 public:
  // CAMERA: kept unless its width or height is not positive or its data is
  // not width * height bytes (then counted in bad_frames(), false).
  bool on_frame(const camera_frame_t& m);
  // ARM_SERVO: kept unless a joint position is not finite (false).
  bool on_state(const joint_state_t& m);

  // The newest state kept; nullopt before the first.
  std::optional<joint_state_t> state() const;
  // The capture utime of the newest frame kept (wall clock, us); 0 before the first.
  int64_t frame_utime() const { return frame_utime_; }
  // A copy of the newest frame kept (0 x 0 before the first).
  GreyFrame frame() const;
  int64_t bad_frames() const { return bad_frames_; }

 private:
  mutable std::mutex mutex_;
  camera_frame_t frame_;
  std::atomic<int64_t> frame_utime_{0};
  std::optional<joint_state_t> state_;
  std::atomic<int64_t> bad_frames_{0};
};

// The joints of a servo state, rad.
arm::Joints joints_of(const joint_state_t& s);

// Where a move starts: the servo's joints, clamped into `limits` when
// outside by at most JointMove's tolerance, 1e-6 rad (a trajectory whose
// first point is outside by any amount is refused by the servo, which then
// stops the arm with a fault). Throws std::runtime_error naming the joint
// when the servo reports one farther outside.
arm::Joints move_start_of(const joint_state_t& s, const arm::JointLimits& limits);

// The ARM_TRAJECTORY that executes `path`, stamped `utime` (wall clock, us)
// with `seq`.
joint_trajectory_t trajectory_message_of(const JointPath& path, int64_t utime, int64_t seq);

}  // namespace ephor::calibrate
