// Fuzz target (issue 18): an ARM_CMD message as ephor-arm handles it: the
// bytes decoded as arm_cmd_t the way the bus does (a message that does not
// decode to its full size is dropped), converted to an ArmCommand as main.cc
// does, and validated (CommandValidator) against the arm's joints: well-formed
// messages with NaN, infinities, unknown kinds and planes, huge or negative
// point counts, trajectories that break every limit. The motion planning that
// follows an accepted command (OMPL, up to its time budget) is not run here.
//
// The arm's current joints are its park joints; when the message's
// source_frame_utime is odd and it carries a trajectory with a finite first
// point, the arm is taken to be at that point, so the trajectory checks past
// the start are reached too.
//
// Seeds: fuzz_corpus/arm_command (one valid message of each kind).
#include <cstddef>
#include <cstdint>

#include "common/arm/arm_workcell.h"
#include "common/calibration/field_calibration.h"
#include "common/fuzz/fuzz_input.h"
#include "common/geometry/overhead_camera.h"
#include "common/geometry/workcell.h"
#include "ephor/arm_cmd_t.hpp"
#include "procs/shared/arm/arm_cmd_message.h"
#include "procs/shared/arm/command_validator.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const ephor::geometry::Workcell cell;
  static const ephor::geometry::OverheadCamera camera;
  static const ephor::arm::CommandValidator validator(
      ephor::calibration::FieldCalibration::from_camera(camera, cell), cell);
  if (size > 1 << 20) return 0;  // larger than any LCM message the bus takes
  ephor::arm_cmd_t m;
  const int n = static_cast<int>(size);
  if (m.decode(data, 0, n) != n) return 0;
  const ephor::arm::ArmCommand cmd = ephor::arm::command_from_message(m);
  ephor::arm::Joints current = ephor::arm::park_joints(cell);
  if ((m.source_frame_utime & 1) != 0 && !cmd.trajectory.points.empty() &&
      cmd.trajectory.points.front().q.allFinite())
    current = cmd.trajectory.points.front().q;
  const ephor::arm::Validation v = validator.validate(cmd, current);
  if (!v.ok && v.reason.empty()) ephor::fuzz::fail("a refused command carries no reason");
  if (v.ok && !(v.target.goal_q.allFinite() && v.target.speed_mm_s > 0.0 &&
                std::isfinite(v.target.speed_mm_s)))
    ephor::fuzz::fail("an accepted command has a non-finite goal or speed");
  return 0;
}
