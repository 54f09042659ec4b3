// Fuzz target (issue 18): ephor-rambo-pose on any stream of its inputs,
// RAMBO_FEATURES (rambo_features_t), RAMBO_PREDICTION (rambo_prediction_t)
// and ARM_STATE (arm_state_t), as its handlers and pose task take them
// (pose_task.h): each message decoded the way the bus does (a message that
// does not decode to its full size is dropped), the prediction taken by
// prior_motion_of(), the joints by joints_of() (non-finite refused), the
// frames queued by PoseFrameQueue (--max-behind 5, the default) until the
// arm has reported past their capture time, and each frame ready posed by
// FramePoser (the built-in target, the exact method, --prior-max-age-s 1:
// the process's defaults) into the RAMBO_POSE it publishes. Every pose
// published must encode, its camera pose be finite and a rotation, and a
// found pose be finite and a rotation (orthonormal within 1e-6, det +1: the
// predictor drops any other).
//
// Input: up to 64 records, each a byte naming what comes (bits 0-1: 0
// RAMBO_FEATURES, 1 RAMBO_PREDICTION, 2 ARM_STATE, 3 none: the pose task
// catches up; bit 2: the pose task is late, it does not run on this
// message's trigger), then, for a message, a 2-byte length (little-endian)
// and that many bytes. The pose task, when it runs, poses every ready frame
// (one per job, as it re-triggers itself); the ready ones left are posed at
// the end. A features message carries at most
// TrianglePoseOptions::max_triples triples the estimator takes (more are
// refused, counted). Seeds: fuzz_corpus/rambo_pose (the arm at its start
// pose reporting at 100 Hz, frames of the target 800 mm in front of the
// camera, 0.5 px noise, with and without a prediction; a frame of 70
// triples; states and frames at the ends of int64_t; made by a small
// generator with synthetic_image_triples()).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Geometry>

#include "common/fuzz/fuzz_input.h"
#include "common/rambo/rambo_cell.h"
#include "common/rambo/target_model_file.h"
#include "common/rambo/triangle_pose_estimator.h"
#include "procs/rambo/pose/pose_task.h"

namespace {

using namespace ephor;
using namespace ephor::rambo;

bool is_rotation(const double* r) {
  Eigen::Matrix3d m;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) m(i, j) = r[3 * i + j];
  if (!m.allFinite()) return false;
  return (m.transpose() * m - Eigen::Matrix3d::Identity()).norm() < 1e-6 && m.determinant() > 0.0;
}

void check(const rambo_pose_t& out) {
  for (double v : out.camera_t_mm)
    if (!std::isfinite(v)) fuzz::fail("a camera position that is not finite");
  if (!is_rotation(out.camera_r)) fuzz::fail("a camera orientation that is not a rotation");
  if (out.found) {
    for (double v : out.target_t_mm)
      if (!std::isfinite(v)) fuzz::fail("a found pose's position is not finite");
    if (!is_rotation(out.target_r)) fuzz::fail("a found pose's orientation is not a rotation");
    if (!std::isfinite(out.rms_reprojection_px) || out.rms_reprojection_px < 0.0)
      fuzz::fail("a found pose's reprojection error is not finite");
  }
  const int size = out.getEncodedSize();
  if (size < 0) fuzz::fail("the pose has no encoded size");
  std::vector<uint8_t> bytes(static_cast<size_t>(size));
  if (out.encode(bytes.data(), 0, size) != size) fuzz::fail("the pose does not encode");
}

struct Process {
  RamboCell cell = cell_from_flags("", 0);
  TrianglePoseEstimator estimator{cell.model, cell.camera, TrianglePoseOptions{}};
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const Process process;  // the cell and estimator do not change with the input
  PoseFrameQueue frames(5);
  FramePoser poser(process.cell, process.estimator, 1.0);
  auto run_task = [&] {
    while (std::optional<ReadyFrame> rf = frames.take()) {
      bool malformed = false;
      check(poser.pose(*rf, &malformed));
    }
  };
  size_t at = 0;
  for (int k = 0; k < 64 && at < size; ++k) {
    const int what = data[at] & 3;
    const bool late = (data[at] & 4) != 0;
    ++at;
    if (what == 3) {
      run_task();
      continue;
    }
    if (at + 2 > size) break;
    const size_t len = data[at] | (static_cast<size_t>(data[at + 1]) << 8);
    at += 2;
    if (len > size - at) break;
    const int n = static_cast<int>(len);
    const uint8_t* bytes = data + at;
    at += len;
    bool trigger = false;
    if (what == 0) {
      rambo_features_t m;
      if (m.decode(bytes, 0, n) != n) continue;
      trigger = frames.on_features(m);
    } else if (what == 1) {
      rambo_prediction_t m;
      if (m.decode(bytes, 0, n) != n) continue;
      if (const std::optional<FittedMotion> fm = prior_motion_of(m)) frames.on_motion(*fm);
    } else {
      arm_state_t m;
      if (m.decode(bytes, 0, n) != n) continue;
      const std::optional<arm::Joints> q = joints_of(m);
      if (!q) continue;
      trigger = frames.on_arm_state(m.utime, *q);
    }
    if (trigger && !late) run_task();
  }
  run_task();
  return 0;
}
